// app/assets.cpp - bundled asset lookup.
#include "app/assets.hpp"

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "core/error.hpp"

#ifndef TRIDEX_SOURCE_ASSETS
#define TRIDEX_SOURCE_ASSETS "assets"
#endif

namespace tridex::app {

std::string bundled_asset(const std::string& name, const std::string& what, const std::string& hint) {
    namespace fs = std::filesystem;
    std::vector<fs::path> candidates;
    if (const char* env = std::getenv("TRIDEX_ASSETS")) candidates.emplace_back(fs::path(env) / name);
    candidates.emplace_back(fs::path("assets") / name);
    candidates.emplace_back(fs::path(TRIDEX_SOURCE_ASSETS) / name);
    for (const fs::path& p : candidates)
        if (fs::is_regular_file(p)) return p.string();
    throw Error("assets/" + name + ": the bundled " + what + " is missing; " + hint);
}

std::string default_mesh_path() { return bundled_asset("bunny.off", "workpiece", "pass --mesh FILE"); }

}  // namespace tridex::app
