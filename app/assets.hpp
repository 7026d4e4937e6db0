// app/assets.hpp - finding the files the program ships in assets/.
#pragma once

#include <string>

namespace tridex::app {

/// Path of the bundled asset `name` (e.g. "bunny.off"): looked up in $TRIDEX_ASSETS, then ./assets,
/// then the source tree's assets/ (compile-time path). Throws tridex::Error "assets/<name>: the bundled
/// <what> is missing; <hint>" when none exists.
std::string bundled_asset(const std::string& name, const std::string& what, const std::string& hint);

}  // namespace tridex::app
