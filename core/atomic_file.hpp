// core/atomic_file.hpp - writing a file so that a crash or a full disk never destroys the previous one: the
// bytes go to an unnamed temporary file in the target's folder (Linux O_TMPFILE; "<path>.tmp-<pid>" where the file
// system has none), are flushed and fsync'ed, then given the temporary name, renamed over <path> and the folder
// fsync'ed. A process killed before the rename (even by SIGKILL) leaves no file behind on a file system with
// O_TMPFILE.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace tridex {

/// One file being written atomically. Construction creates the temporary file in `path`'s folder (unnamed where the
/// file system supports O_TMPFILE); write() appends (every write checked); commit() makes it `path`. Destroying an
/// uncommitted AtomicFile removes the temporary file and leaves `path` as it was. Move-only. Errors are
/// tridex::Error "<path>: <what> (<strerror>)", e.g. "out/m.tdx: cannot write: No space left on device".
class AtomicFile {
public:
    /// Opens an unnamed temporary file in the folder of `path` (O_TMPFILE), or, where the file system refuses one,
    /// creates "<path>.tmp-<pid>" (truncating a stale one). Throws tridex::Error when it cannot.
    explicit AtomicFile(std::string path);
    ~AtomicFile();
    AtomicFile(AtomicFile&& other) noexcept;
    AtomicFile& operator=(AtomicFile&&) = delete;
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// Appends n bytes. Throws tridex::Error on a short write (full disk, file size limit, I/O error).
    void write(const void* data, std::size_t n);
    /// Appends the bytes of `s`. Throws as write(data, n).
    void write(std::string_view s) { write(s.data(), s.size()); }
    /// The open stream, for formatted output (std::fprintf); its errors are caught by commit(). nullptr after
    /// commit().
    std::FILE* stream() { return file_; }
    /// fflush + fsync, the unnamed file linked as temp_path() (linkat through /proc/self/fd), fclose, rename over
    /// path(), fsync of the folder. Throws tridex::Error on any failure (the temporary file is then removed and
    /// path() untouched). Once only.
    void commit();
    /// The final path.
    const std::string& path() const { return path_; }
    /// The temporary name the file has just before it is renamed over path() ("<path>.tmp-<pid>"); with a named
    /// temporary file (unnamed() false) the bytes go there from the start.
    const std::string& temp_path() const { return temp_; }
    /// True when the bytes go to an unnamed file (O_TMPFILE) that has no name in the folder until commit().
    bool unnamed() const { return unnamed_; }

private:
    void discard() noexcept;

    std::string path_, temp_;
    std::FILE* file_ = nullptr;
    bool committed_ = false;
    bool unnamed_ = false;  // O_TMPFILE: no name until commit() links it as temp_
    bool linked_ = false;   // temp_ exists on disk (named from the start, or linked by commit())
};

/// Writes `bytes` to `path` through an AtomicFile. Throws as AtomicFile.
void write_file_atomically(const std::string& path, std::string_view bytes);

/// "<path>.tmp-<pid>": where a writer that opens files itself (e.g. a mesh library) writes before
/// commit_temp_file().
std::string temp_path_for(const std::string& path);

/// Makes the finished file `temp` (written and closed by someone else) `path`: fsync of temp, rename, fsync of
/// the folder. Throws tridex::Error "<path>: ..." (temp removed) on failure.
void commit_temp_file(const std::string& temp, const std::string& path);

}  // namespace tridex
