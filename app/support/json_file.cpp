// app/support/json_file.cpp - one JSON file writer for reports and benchmarks.
#include "app/support/json_file.hpp"

#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/text/json_refusal.hpp"

namespace tridex::app {

nlohmann::json read_scene_json(const std::string& path) {
    if (std::filesystem::is_directory(path)) throw Error(path + ": is a folder; name a scene file (JSON)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot read the scene file");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {  // the line and column and what was expected; 1e400 and its field
        throw Error(path + ": not valid JSON: " + json_refusal<nlohmann::json>(text, e));
    }
}

void write_json_file(const std::string& path, const nlohmann::json& j) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    write_file_atomically(path, j.dump(2) + "\n");
}

}  // namespace tridex::app
