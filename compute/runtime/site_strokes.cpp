// compute/runtime/site_strokes.cpp - the sites of the undo history's strokes, for personal undo.
#include "compute/runtime/site_strokes.hpp"

namespace tridex::app {

void SiteStrokes::opened() {
    open_.site = sweeps_.open_site();
    if (!sweeps_.interrupted_by(open_.site)) gesture_since_[open_.site] = last_kept_;  // a new gesture
    open_.since = gesture_since_[open_.site];
}

void SiteStrokes::closed(std::uint64_t serial, bool kept, std::optional<std::uint8_t> by_site) {
    if (kept && serial != 0) {
        steps_[serial] = open_;
        last_kept_ = serial;
    }
    sweeps_.stroke_closed(by_site);
    open_ = Tag{};
}

std::optional<std::uint8_t> SiteStrokes::blocks_undo(std::uint8_t site, std::uint64_t serial) const {
    if (serial == 0) return std::nullopt;
    const auto it = steps_.find(serial);
    const Tag t = it == steps_.end() ? Tag{0, serial - 1} : it->second;
    if (t.site != site) return t.site;
    for (auto k = steps_.upper_bound(t.since); k != steps_.end() && k->first < serial; ++k)
        if (k->second.site != site) return k->second.site;
    return std::nullopt;
}

bool SiteStrokes::same_gesture(std::uint64_t a, std::uint64_t b) const {
    const auto ia = steps_.find(a), ib = steps_.find(b);
    if (ia == steps_.end() || ib == steps_.end()) return a == b;
    return ia->second.site == ib->second.site && ia->second.since == ib->second.since;
}

std::optional<std::uint8_t> SiteStrokes::blocks_redo(std::uint8_t site, std::uint64_t serial) const {
    if (serial == 0) return std::nullopt;
    const auto it = steps_.find(serial);
    const std::uint8_t owner = it == steps_.end() ? 0 : it->second.site;
    return owner != site ? std::optional<std::uint8_t>(owner) : std::nullopt;
}

}  // namespace tridex::app
