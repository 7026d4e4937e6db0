// core/atomic_file.hpp - files written whole or not at all: a temporary file beside the target, every write checked,
// flushed to the disk, then renamed over the target.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace tridex {

/// A file that replaces `path` only when commit() succeeds. The bytes go to a temporary file in the same folder
/// ("<path>.tmp-<pid>-<n>"); commit() flushes it, fsyncs it, closes it (all checked), renames it over `path` and
/// fsyncs the folder, so a crash, a full disk or an I/O error at any point leaves either the previous file or the
/// complete new one, never a cut one. Without commit() (an exception, an early return) the destructor removes the
/// temporary file. Not thread-safe; one writer per object.
class AtomicFile {
public:
    /// Creates the temporary file. Throws tridex::Error "<path>: cannot create: <reason>".
    explicit AtomicFile(std::string path);
    /// Removes the temporary file unless committed. Never throws.
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// Appends `n` bytes. Throws tridex::Error "<path>: write failed: <reason>" (e.g. "No space left on device").
    void write(const void* data, std::size_t n);
    /// Appends the bytes of `s`. Throws as write(data, n).
    void write(std::string_view s) { write(s.data(), s.size()); }
    /// The open stream, for formatted output (std::fprintf); its errors are caught by commit().
    std::FILE* stream() { return f_; }
    /// Makes the new content the file at `path` (see the class comment). Throws tridex::Error "<path>: write failed:
    /// <reason>" or "<path>: cannot replace: <reason>"; the previous file is then untouched. Once only.
    void commit();
    /// The target path.
    const std::string& path() const { return path_; }

private:
    [[noreturn]] void fail(const char* what, int err);

    std::string path_, tmp_;
    std::FILE* f_ = nullptr;
    bool committed_ = false;
};

/// Writes `bytes` to `path` through an AtomicFile. Throws as AtomicFile.
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace tridex
