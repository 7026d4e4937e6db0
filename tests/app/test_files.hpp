// tests/app/test_files.hpp - what the app tests read back: a file's bytes, a JSON file, and the `tridex` executable
// run as a user runs it.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>
#include "../test_paths.hpp"

namespace tridex::app::test {

/// The whole file as bytes ("" when it cannot be read).
inline std::string bytes_of(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The file parsed as JSON (throws nlohmann::json::parse_error when it is not).
inline nlohmann::json read_json(const std::filesystem::path& p) {
    std::ifstream in(p);
    return nlohmann::json::parse(in);
}

/// How a run of the executable ended.
struct ExeResult {
    int exit_code = -1;  ///< the exit status, or -1 when it died by a signal
    std::string err;     ///< what it wrote on stderr
};

/// A fresh, empty folder `prefix + name` under the test's temporary folder.
inline std::filesystem::path fresh_test_dir(const std::string& prefix, const std::string& name) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / (prefix + name);
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

/// A session key file of 64 hexadecimal characters, every byte the two characters `b` ("5a"), and a line end.
inline std::filesystem::path hex_key_file(const std::filesystem::path& dir, const std::string& name, const char* b) {
    const std::filesystem::path p = dir / name;
    std::ofstream f(p);
    for (int i = 0; i < 32; ++i) f << b;
    f << "\n";
    return p;
}

/// Runs `tridex ARGS` (shell words) under a 300 s timeout with stdout in dir/stdout.txt and stderr in
/// dir/stderr.txt (dir is created), and waits for it.
inline ExeResult run_tridex(const std::string& args, const std::filesystem::path& dir) {
    std::filesystem::create_directories(dir);
    const std::filesystem::path err = dir / "stderr.txt";
    const std::string cmd = "timeout 300 " + std::string(TRIDEX_EXE) + " " + args + " > " +
                            (dir / "stdout.txt").string() + " 2> " + err.string();
    const int status = std::system(cmd.c_str());
    ExeResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.err = bytes_of(err);
    return r;
}

}  // namespace tridex::app::test
