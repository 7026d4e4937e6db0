// app/json_file.cpp - one JSON file writer for reports and benchmarks.
#include "app/json_file.hpp"

#include <filesystem>
#include <fstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace tridex::app {

void write_json_file(const std::string& path, const nlohmann::json& j) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    write_file_atomically(path, j.dump(2) + "\n");
}

}  // namespace tridex::app
