// app/support/assets.hpp - finding the files the program ships in assets/.
#pragma once

#include <string>

namespace tridex::app {

/// Path of the bundled asset `name` (e.g. "bunny.off"): looked up in $TRIDEX_ASSETS, then ./assets,
/// then the source tree's assets/ (compile-time path). Throws tridex::Error "assets/<name>: the bundled
/// <what> is missing; <hint>" when none exists.
std::string bundled_asset(const std::string& name, const std::string& what, const std::string& hint);

/// The bundled default workpiece (assets/bunny.off), found as bundled_asset finds it. Throws tridex::Error when it
/// is missing.
std::string default_mesh_path();

}  // namespace tridex::app
