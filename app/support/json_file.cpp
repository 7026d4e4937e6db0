// app/support/json_file.cpp - one JSON file writer for reports and benchmarks.
#include "app/support/json_file.hpp"

#include <filesystem>
#include <fstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/printable.hpp"

namespace tridex::app {

std::string json_reason(const nlohmann::json::exception& e) {
    const std::string what = e.what();
    const std::size_t end = what.find("] ");
    // The parser quotes the bytes it last read: made printable, so that the message stays one line of text.
    return printable(end == std::string::npos ? what : what.substr(end + 2), 240);
}

nlohmann::json read_scene_json(const std::string& path) {
    if (std::filesystem::is_directory(path)) throw Error(path + ": is a folder; name a scene file (JSON)");
    std::ifstream in(path);
    if (!in) throw Error(path + ": cannot read the scene file");
    nlohmann::json j;
    try {
        in >> j;
    } catch (const nlohmann::json::exception& e) {  // the line and column and what was expected; 1e400; ...
        throw Error(path + ": not valid JSON: " + json_reason(e));
    }
    return j;
}

void write_json_file(const std::string& path, const nlohmann::json& j) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    write_file_atomically(path, j.dump(2) + "\n");
}

}  // namespace tridex::app
