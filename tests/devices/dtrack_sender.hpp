// A loopback UDP sender that speaks DTrack's ASCII output, for tests of the receiver and the tracked head.
#pragma once

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "core/math.hpp"

namespace tridex::test {

/// Sends datagrams to 127.0.0.1:port.
class DTrackSender {
public:
    explicit DTrackSender(int port) {
        fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
        if (fd_ < 0) throw std::runtime_error("socket");
        to_.sin_family = AF_INET;
        to_.sin_port = htons(static_cast<std::uint16_t>(port));
        to_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    }
    ~DTrackSender() { ::close(fd_); }
    DTrackSender(const DTrackSender&) = delete;
    DTrackSender& operator=(const DTrackSender&) = delete;

    /// Sends `payload` as one datagram; true when the kernel took it.
    bool send(const std::string& payload) const {
        return ::sendto(fd_, payload.data(), payload.size(), 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_) ==
               static_cast<ssize_t>(payload.size());
    }

private:
    int fd_ = -1;
    sockaddr_in to_{};
};

/// A DTrack datagram with frame counter `fr` and one tracked standard body `id` at `position_mm` whose rotation
/// (body -> tracker, a 3x3 matrix) is written column-wise; quality -1 when `tracked` is false.
inline std::string dtrack_datagram(unsigned fr, int id, const Vec3& position_mm, const glm::dmat3& r,
                                   bool tracked = true) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "fr %u\r\nts %.6f\r\n6dcal %d\r\n6d 1 [%d %.3f][%.3f %.3f %.3f 0.0000 0.0000 0.0000]"
                  "[%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f]\r\n",
                  fr, fr / 60.0, id + 1, id, tracked ? 1.0 : -1.0, position_mm.x, position_mm.y, position_mm.z, r[0][0],
                  r[0][1], r[0][2], r[1][0], r[1][1], r[1][2], r[2][0], r[2][1], r[2][2]);
    return buf;
}

/// A DTrack datagram with frame counter `fr` and one Flystick (`6df2`, `defined` Flysticks defined) with id `id`
/// at `position_mm`, rotation `r` (written column-wise), 8 buttons (bit field `buttons`) and 2 controllers
/// (joystick x, y in [-1, 1]); quality -1 when `tracked` is false.
inline std::string dtrack_flystick_datagram(unsigned fr, int id, const Vec3& position_mm, const glm::dmat3& r,
                                            unsigned buttons, double joy_x, double joy_y, bool tracked = true,
                                            int defined = 0) {
    char buf[640];
    std::snprintf(buf, sizeof buf,
                  "fr %u\r\nts %.6f\r\n6df2 %d 1 [%d %.3f 8 2][%.3f %.3f %.3f]"
                  "[%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f][%u %.4f %.4f]\r\n",
                  fr, fr / 60.0, defined > 0 ? defined : id + 1, id, tracked ? 1.0 : -1.0, position_mm.x,
                  position_mm.y, position_mm.z, r[0][0], r[0][1], r[0][2], r[1][0], r[1][1], r[1][2], r[2][0], r[2][1],
                  r[2][2], buttons, joy_x, joy_y);
    return buf;
}

/// Rotation by `deg` degrees about +y.
inline glm::dmat3 rotation_y_deg(double deg) {
    const double a = deg * M_PI / 180.0, c = std::cos(a), s = std::sin(a);
    glm::dmat3 m(1.0);
    m[0] = Vec3(c, 0, -s);  // image of x
    m[2] = Vec3(s, 0, c);   // image of z
    return m;
}

/// A 4x4 matrix from a rotation (columns) and a translation (m): the tests' independent reference for pose chains.
inline glm::dmat4 rigid(const glm::dmat3& r, const Vec3& t) {
    glm::dmat4 m(r);
    m[3] = glm::dvec4(t, 1.0);
    return m;
}

}  // namespace tridex::test
