// app/session/run/run_options.cpp - display kind names.
#include "app/session/run/run_options.hpp"

#include "core/error.hpp"

namespace tridex::app {

const char* to_string(DisplayKind kind) {
    switch (kind) {
        case DisplayKind::kWindow: return "window";
        case DisplayKind::kFullscreen: return "fullscreen";
        case DisplayKind::kOffscreen: return "offscreen";
    }
    return "window";
}

DisplayKind parse_display_kind(const std::string& name) {
    for (DisplayKind k : {DisplayKind::kWindow, DisplayKind::kFullscreen, DisplayKind::kOffscreen})
        if (name == to_string(k)) return k;
    throw Error("--display: '" + name + "' is not one of window, fullscreen, offscreen");
}

}  // namespace tridex::app
