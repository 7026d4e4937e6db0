// tests/fuzz/fuzz_support.hpp - what every libFuzzer target of a reader shares: the fuzz bytes as a file for
// readers that take a path, and the rule that a refusal is a tridex::Error whose one printable line names the
// file. Anything else (a crash, a sanitizer report, another exception, a bad refusal) aborts: a finding.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "core/error.hpp"

namespace tridex::fuzz {

/// A private temporary folder for this process's input files, removed when the process ends: in $TMPDIR, else in
/// /dev/shm (memory; rewriting a file on a disk file system can wait for the disk on every input), else in /tmp.
class ScratchFolder {
public:
    /// Makes the folder; aborts when it cannot (no input could be read then).
    ScratchFolder() {
        const char* tmp = std::getenv("TMPDIR");
        std::error_code ec;
        const std::string base = tmp && *tmp ? tmp : std::filesystem::is_directory("/dev/shm", ec) ? "/dev/shm" : "/tmp";
        std::string tmpl = base + "/tridex-fuzz-XXXXXX";
        if (!mkdtemp(tmpl.data())) {
            std::perror("tridex fuzz: mkdtemp");
            std::abort();
        }
        path_ = tmpl;
    }
    /// Removes the folder and what is in it.
    ~ScratchFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ScratchFolder(const ScratchFolder&) = delete;
    ScratchFolder& operator=(const ScratchFolder&) = delete;
    /// The folder's path.
    const std::string& path() const { return path_; }

private:
    std::string path_;
};

/// The file `name` in this process's scratch folder, holding `data` (rewritten on every call).
inline std::string input_file(const std::string& name, const std::uint8_t* data, std::size_t size) {
    static ScratchFolder folder;
    const std::string path = folder.path() + "/" + name;
    std::remove(path.c_str());  // a new file each time: truncating one in place can wait for the disk
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) {
        std::fprintf(stderr, "tridex fuzz: cannot write %s\n", path.c_str());
        std::abort();
    }
    return path;
}

/// `data` as the bytes of a file.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

/// Aborts (a finding) unless `message` is one line of printable ASCII that names `file`.
inline void check_refusal(std::string_view message, std::string_view file) {
    bool printable = !message.empty();
    for (const char ch : message) {
        const auto c = static_cast<unsigned char>(ch);
        printable = printable && c >= 0x20 && c < 0x7f;
    }
    if (printable && message.find(file) != std::string_view::npos) return;
    std::fprintf(stderr, "tridex fuzz: a refusal that is not one printable line naming '%.*s': '%.*s'\n",
                 static_cast<int>(file.size()), file.data(), static_cast<int>(message.size()), message.data());
    std::abort();
}

/// Runs `read` (a reader applied to the fuzz input of `file`): returning or throwing a tridex::Error that passes
/// check_refusal is fine; any other exception escapes and ends the process (a finding).
template <class Read>
void expect_clean(std::string_view file, Read&& read) {
    try {
        read();
    } catch (const tridex::Error& e) {
        check_refusal(e.what(), file);
    }
}

}  // namespace tridex::fuzz
