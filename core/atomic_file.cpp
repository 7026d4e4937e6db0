// core/atomic_file.cpp - temporary file, fsync, rename, fsync of the folder (POSIX).
#include "core/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "core/error.hpp"

namespace tridex {

namespace {

std::string why(int err) { return std::strerror(err); }

std::string folder_of(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return ".";
    if (slash == 0) return "/";
    return path.substr(0, slash);
}

void fsync_path(const std::string& p, int flags, const std::string& name_for_error) {
    const int fd = ::open(p.c_str(), flags | O_CLOEXEC);
    if (fd < 0) throw Error(name_for_error + ": cannot open for fsync (" + why(errno) + ")");
    const int rc = ::fsync(fd);
    const int err = errno;
    ::close(fd);
    // Some file systems cannot fsync a folder (EINVAL); the rename itself still happened.
    if (rc != 0 && !(flags & O_DIRECTORY && (err == EINVAL || err == EROFS)))
        throw Error(name_for_error + ": fsync failed (" + why(err) + ")");
}

}  // namespace

std::string temp_path_for(const std::string& path) { return path + ".tmp-" + std::to_string(::getpid()); }

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), temp_(temp_path_for(path_)) {
    // An unnamed file in the target's folder (same file system, so the final rename is atomic). File systems
    // without O_TMPFILE answer EOPNOTSUPP (or EISDIR, EINVAL on old kernels): then a named temporary file.
    const int fd = ::open(folder_of(path_).c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (fd >= 0) {
        file_ = ::fdopen(fd, "wb");
        if (!file_) {
            const int err = errno;
            ::close(fd);
            throw Error(path_ + ": cannot open a temporary file (" + why(err) + ")");
        }
        unnamed_ = true;
        return;
    }
    file_ = std::fopen(temp_.c_str(), "wb");
    if (!file_) throw Error(path_ + ": cannot create " + temp_ + " (" + why(errno) + ")");
    linked_ = true;
}

AtomicFile::AtomicFile(AtomicFile&& o) noexcept
    : path_(std::move(o.path_)), temp_(std::move(o.temp_)), file_(std::exchange(o.file_, nullptr)),
      committed_(std::exchange(o.committed_, true)), unnamed_(o.unnamed_), linked_(std::exchange(o.linked_, false)) {}

AtomicFile::~AtomicFile() {
    if (!committed_) discard();
}

void AtomicFile::discard() noexcept {
    if (file_) std::fclose(file_);
    file_ = nullptr;
    if (linked_) ::unlink(temp_.c_str());
    linked_ = false;
}

void AtomicFile::write(const void* data, std::size_t n) {
    if (!file_) throw Error(path_ + ": write after commit");
    if (n == 0) return;
    errno = 0;
    if (std::fwrite(data, 1, n, file_) != n) {
        const int err = errno ? errno : EIO;
        discard();
        throw Error(path_ + ": cannot write (" + why(err) + "); the previous file, if any, is unchanged");
    }
}

void AtomicFile::commit() {
    if (!file_) throw Error(path_ + ": commit twice");
    errno = 0;
    if (std::ferror(file_) || std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) {
        const int err = errno ? errno : EIO;
        discard();
        throw Error(path_ + ": cannot write (" + why(err) + "); the previous file, if any, is unchanged");
    }
    if (unnamed_) {  // the unnamed file gets its temporary name only now, for the rename
        const std::string self = "/proc/self/fd/" + std::to_string(::fileno(file_));
        ::unlink(temp_.c_str());  // a stale one of an earlier process with this pid
        if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, temp_.c_str(), AT_SYMLINK_FOLLOW) != 0) {
            const int err = errno;
            discard();
            throw Error(path_ + ": cannot name the temporary file " + temp_ + " (" + why(err) + ")");
        }
        linked_ = true;
    }
    const int rc = std::fclose(file_);
    file_ = nullptr;
    if (rc != 0) {
        const int err = errno;
        discard();
        throw Error(path_ + ": cannot write (" + why(err) + "); the previous file, if any, is unchanged");
    }
    if (::rename(temp_.c_str(), path_.c_str()) != 0) {
        const int err = errno;
        discard();
        throw Error(path_ + ": cannot rename " + temp_ + " over it (" + why(err) + ")");
    }
    committed_ = true;
    linked_ = false;
    fsync_path(folder_of(path_), O_RDONLY | O_DIRECTORY, path_ + " (folder)");
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
    AtomicFile f(path);
    f.write(bytes);
    f.commit();
}

void commit_temp_file(const std::string& temp, const std::string& path) {
    try {
        fsync_path(temp, O_RDONLY, path);
    } catch (...) {
        ::unlink(temp.c_str());
        throw;
    }
    if (::rename(temp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        ::unlink(temp.c_str());
        throw Error(path + ": cannot rename " + temp + " over it (" + why(err) + ")");
    }
    fsync_path(folder_of(path), O_RDONLY | O_DIRECTORY, path + " (folder)");
}

}  // namespace tridex
