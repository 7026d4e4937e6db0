// devices/spacemouse_device.cpp - spacenavd's AF_UNIX event stream, non-blocking, into rate-controlled motion.
#include "devices/spacemouse_device.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <cmath>
#include <cstring>
#include <utility>

#include "core/error.hpp"
#include "devices/rotation_vector.hpp"

namespace tridex::devices {

namespace {
constexpr int kMaxPacketsPerRead = 256;  // a flood is read over several ticks, never in one
constexpr int kAxisLimit = 32767;
}  // namespace

std::string spnav_socket_from_config(const std::string& config_path) {
    std::ifstream in(config_path);
    for (std::string line; in && std::getline(in, line);) {
        const std::size_t b = line.find_first_not_of(" \t\r");
        if (b == std::string::npos || line[b] == '#' || line.compare(b, 6, "socket") != 0) continue;
        const std::size_t eq = line.find('=', b + 6);
        if (eq == std::string::npos || line.find_first_not_of(" \t", b + 6) != eq) continue;
        const std::size_t v = line.find_first_not_of(" \t", eq + 1);
        if (v == std::string::npos) continue;
        const std::size_t e = line.find_last_not_of(" \t\r");
        return line.substr(v, e - v + 1);
    }
    return "";
}

std::string spnav_socket_path(const std::string& serial, const std::string& env, const std::string& config_path) {
    if (!serial.empty()) return serial;
    if (!env.empty()) return env;
    const std::string rc = spnav_socket_from_config(config_path);
    return rc.empty() ? std::string(kSpnavDefaultSocket) : rc;
}

SpnavPacket decode_spnav_packet(const std::array<std::int32_t, 8>& w) {
    SpnavPacket p;
    switch (w[0]) {
        case 0:
            for (int i = 0; i < 6; ++i) {
                if (w[i + 1] < -kAxisLimit || w[i + 1] > kAxisLimit) return p;
                p.axes[i] = w[i + 1];
            }
            p.kind = SpnavPacket::Kind::kMotion;
            return p;
        case 1:
        case 2:
            if (w[1] < 0 || w[1] >= kSpnavMaxButtons) return p;
            p.button = w[1];
            p.kind = w[0] == 1 ? SpnavPacket::Kind::kPress : SpnavPacket::Kind::kRelease;
            return p;
        case 3: case 4: case 5: case 6:
            p.kind = SpnavPacket::Kind::kOther;
            return p;
        default:
            return p;
    }
}

SpaceMouseDevice::SpaceMouseDevice(DeviceProfile profile, const Vec3& start_m, double dt_s, SpaceMouseParams params)
    : profile_(std::move(profile)), dt_(dt_s), params_(std::move(params)) {
    if (!(std::isfinite(dt_) && dt_ > 0.0 && dt_ <= 1.0)) throw Error("SpaceMouseDevice: dt_s must be in (0, 1] s");
    if (!is_finite(start_m)) throw Error("SpaceMouseDevice: the start position must be finite");
    const SpaceMouseParams& p = params_;
    if (!(std::isfinite(p.full_scale) && p.full_scale > 0.0 && p.dead_zone >= 0.0 && p.dead_zone < 1.0 &&
          std::isfinite(p.max_speed_m_s) && p.max_speed_m_s > 0.0 && std::isfinite(p.max_rate_rad_s) &&
          p.max_rate_rad_s > 0.0))
        throw Error("SpaceMouseDevice: full_scale, max_speed_m_s, max_rate_rad_s must be > 0, dead_zone in [0, 1)");
    if (p.socket_path.empty() || p.socket_path.size() >= sizeof(sockaddr_un::sun_path))
        throw Error("spacemouse: socket path '" + p.socket_path + "' is empty or too long");
    pose_.position = glm::clamp(start_m, profile_.workspace_m.lo, profile_.workspace_m.hi);
}

SpaceMouseDevice::~SpaceMouseDevice() { on_close(); }

std::string spnav_reachable(const std::string& socket_path) {
    if (socket_path.empty() || socket_path.size() >= sizeof(sockaddr_un::sun_path))
        return "the spacenavd socket path '" + socket_path + "' is empty or too long";
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return std::string("socket: ") + std::strerror(errno);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, socket_path.c_str(), socket_path.size() + 1);
    const int rc = ::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr);
    const int e = errno;
    ::close(fd);
    if (rc == 0) return "";
    if (e == ENOENT || e == ECONNREFUSED || e == ENOTSOCK)
        return "no spacenavd at " + socket_path + " (is the daemon running? Debian package spacenavd)";
    return "cannot connect to spacenavd at " + socket_path + ": " + std::strerror(e);
}

void SpaceMouseDevice::on_open() {
    const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) throw Error(std::string("spacemouse: socket: ") + std::strerror(errno));
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::memcpy(addr.sun_path, params_.socket_path.c_str(), params_.socket_path.size() + 1);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
        const int e = errno;
        ::close(fd);
        if (e == ENOENT || e == ECONNREFUSED || e == ENOTSOCK)
            throw Error("spacemouse: no spacenavd at " + params_.socket_path +
                        ": is the daemon running? (Debian package spacenavd)");
        throw Error("spacemouse: cannot connect to spacenavd at " + params_.socket_path + ": " + std::strerror(e));
    }
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
    fd_ = fd;
    vanished_ = false;
    have_ = 0;
    axes_ = {};
    buttons_ = 0;
    reported_buttons_ = 0;
}

void SpaceMouseDevice::on_close() noexcept {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
}

double SpaceMouseDevice::shaped(int counts) const {
    const double a = std::clamp(static_cast<double>(counts) / params_.full_scale, -1.0, 1.0);
    const double m = std::abs(a);
    if (m <= params_.dead_zone) return 0.0;
    return std::copysign((m - params_.dead_zone) / (1.0 - params_.dead_zone), a);
}

void SpaceMouseDevice::apply(const SpnavPacket& p) {
    switch (p.kind) {
        case SpnavPacket::Kind::kMotion: axes_ = p.axes; break;
        case SpnavPacket::Kind::kPress: buttons_ |= std::uint64_t{1} << p.button; break;
        case SpnavPacket::Kind::kRelease: buttons_ &= ~(std::uint64_t{1} << p.button); break;
        case SpnavPacket::Kind::kOther: break;
        case SpnavPacket::Kind::kMalformed: ++stats_.malformed_frames; break;
    }
}

void SpaceMouseDevice::drain() {
    for (int n = 0; n < kMaxPacketsPerRead; ++n) {
        const ssize_t got = ::recv(fd_, partial_.data() + have_, partial_.size() - have_, MSG_DONTWAIT);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
        if (got <= 0) {  // closed by the daemon, or a socket error: the device is gone
            vanished_ = true;
            have_ = 0;
            axes_ = {};
            buttons_ = 0;
            on_close();
            raise_fault(kFaultVanished);
            return;
        }
        have_ += static_cast<std::size_t>(got);
        if (have_ < partial_.size()) continue;  // a packet split across writes: wait for its rest
        std::array<std::int32_t, 8> words{};
        std::memcpy(words.data(), partial_.data(), partial_.size());
        have_ = 0;
        apply(decode_spnav_packet(words));
    }
}

bool SpaceMouseDevice::do_read(DeviceState& out) {
    ++stats_.exchanges;
    if (fd_ >= 0) drain();
    if (vanished_) ++stats_.missed_frames;
    const Vec3 before = pose_.position;
    if (fd_ >= 0) {
        // spacenavd's frame is left-handed (z into the screen); the device frame is right-handed (z toward the
        // viewer): z and rz change sign, as libspnav's own spnav_posrot_moveobj does.
        const Vec3 v(shaped(axes_[0]), shaped(axes_[1]), -shaped(axes_[2]));
        const Vec3 w(shaped(axes_[3]), shaped(axes_[4]), -shaped(axes_[5]));
        pose_.position = glm::clamp(pose_.position + v * (params_.max_speed_m_s * dt_), profile_.workspace_m.lo,
                                    profile_.workspace_m.hi);
        if (w != Vec3(0.0))
            pose_.orientation =
                glm::normalize(quat_from_rotation_vector(w * (params_.max_rate_rad_s * dt_)) * pose_.orientation);
    }
    ++steps_;
    out.t_s = static_cast<double>(steps_) * dt_;
    out.pose = pose_;
    out.velocity_m_s = (pose_.position - before) / dt_;
    reported_buttons_ = buttons_;
    out.buttons = static_cast<std::uint32_t>(buttons_ & 0xffffffffu);
    return true;
}

void SpaceMouseDevice::do_write(const Vec3& /*force_n*/, const Vec3& /*torque_nm*/) {}

}  // namespace tridex::devices
