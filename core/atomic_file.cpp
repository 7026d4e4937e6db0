// core/atomic_file.cpp - temporary file, checked writes, fsync, rename.
#include "core/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/error.hpp"

namespace tridex {

namespace {

std::atomic<unsigned> g_counter{0};

// fsync of the folder holding `path`, so the rename itself survives a power loss; best effort.
void sync_folder(const std::string& path) {
    const std::filesystem::path parent = std::filesystem::path(path).parent_path();
    const int fd = ::open(parent.empty() ? "." : parent.c_str(), O_RDONLY | O_DIRECTORY);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

}  // namespace

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
    tmp_ = path_ + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(g_counter.fetch_add(1));
    f_ = std::fopen(tmp_.c_str(), "wb");
    if (!f_) throw Error(path_ + ": cannot create: " + std::strerror(errno));
}

AtomicFile::~AtomicFile() {
    if (f_) std::fclose(f_);
    if (!committed_) std::remove(tmp_.c_str());
}

void AtomicFile::fail(const char* what, int err) {
    throw Error(path_ + ": " + what + ": " + std::strerror(err ? err : EIO));
}

void AtomicFile::write(const void* data, std::size_t n) {
    if (committed_ || !f_) throw Error(path_ + ": write after commit");
    if (n == 0) return;
    errno = 0;
    if (std::fwrite(data, 1, n, f_) != n) fail("write failed", errno);
}

void AtomicFile::commit() {
    if (committed_ || !f_) throw Error(path_ + ": committed twice");
    errno = 0;
    if (std::ferror(f_)) fail("write failed", errno);
    if (std::fflush(f_) != 0) fail("write failed", errno);
    if (::fsync(::fileno(f_)) != 0 && errno != EINVAL && errno != EROFS) fail("write failed", errno);
    const int rc = std::fclose(f_);
    f_ = nullptr;
    if (rc != 0) fail("write failed", errno);
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0) fail("cannot replace", errno);
    committed_ = true;
    sync_folder(path_);
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
    AtomicFile f(path);
    f.write(bytes);
    f.commit();
}

}  // namespace tridex
