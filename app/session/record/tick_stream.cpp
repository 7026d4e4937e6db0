// app/session/record/tick_stream.cpp - a recording streamed to an unnamed temporary file while the session runs.
#include "app/session/record/tick_stream.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

#include "app/session/record/session_recording.hpp"
#include "core/error.hpp"
#include "devices/recording.hpp"

namespace tridex::app {

namespace {

// An unnamed file in `folder` (O_TMPFILE), else an anonymous one in the system's temporary folder.
std::FILE* open_unnamed(const std::string& folder) {
    const int fd = ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd >= 0) {
        if (std::FILE* f = ::fdopen(fd, "w+b")) return f;
        ::close(fd);
    }
    return std::tmpfile();
}

}  // namespace

TickStream::TickStream(const SessionSpec& spec, std::string path)
    : spec_(spec), path_(std::move(path)), op_(parse_tool_op(spec.op)) {
    std::filesystem::path folder = std::filesystem::path(path_).parent_path();
    if (folder.empty()) folder = ".";
    tmp_ = open_unnamed(folder.string());
    if (!tmp_) throw Error(path_ + ": cannot open a temporary file for the recording (" + std::strerror(errno) + ")");
}

TickStream::~TickStream() {
    stop();
    if (tmp_) std::fclose(tmp_);
}

void TickStream::start() {
    if (thread_.joinable()) return;
    running_.store(true, std::memory_order_release);
    thread_ = std::thread([this] { drain(); });
}

void TickStream::stop() {
    running_.store(false, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
}

void TickStream::drain() {
    double prev_t_s = -INFINITY;
    haptics::TickRecord rec;
    for (;;) {
        // Read the flag before emptying the ring: a record pushed before stop() is then drained by this pass.
        const bool last = !running_.load(std::memory_order_acquire);
        bool any = false;
        while (ring_.try_pop(rec)) {
            any = true;
            const devices::RecordedTick t = to_recorded_tick(rec, op_, prev_t_s, spec_.points);
            prev_t_s = t.t_s;
            if (!error_.empty()) continue;  // keep draining so the loop never finds the ring full
            if (std::fwrite(&t, sizeof t, 1, tmp_) != 1) {
                error_ = std::string("cannot write the recording's temporary file (") + std::strerror(errno) + ")";
                continue;
            }
            ticks_.fetch_add(1, std::memory_order_relaxed);
        }
        if (last) return;
        if (!any) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

void TickStream::finish(const std::string& notes, std::span<const SculptMark> marks, const std::string& menu,
                        std::span<const std::vector<SculptMark>> more_marks,
                        std::span<const haptics::PoseChange> poses) {
    stop();
    if (!error_.empty()) throw Error(path_ + ": " + error_);
    if (!tmp_ || std::fflush(tmp_) != 0 || std::fseek(tmp_, 0, SEEK_SET) != 0)
        throw Error(path_ + ": cannot read the recording's temporary file back (" + std::strerror(errno) + ")");
    devices::RecordingHeader header = recording_header(spec_, notes, marks, more_marks, poses);
    header.menu = menu;
    devices::RecordingWriter writer(path_, header);
    std::vector<devices::RecordedTick> chunk(4096);
    for (std::size_t left = ticks(); left > 0;) {
        const std::size_t want = std::min(left, chunk.size());
        if (std::fread(chunk.data(), sizeof(devices::RecordedTick), want, tmp_) != want)
            throw Error(path_ + ": cannot read the recording's temporary file back (" + std::strerror(errno) + ")");
        for (std::size_t i = 0; i < want; ++i) writer.write(chunk[i]);
        left -= want;
    }
    writer.close();
    std::fclose(tmp_);
    tmp_ = nullptr;
}

}  // namespace tridex::app
