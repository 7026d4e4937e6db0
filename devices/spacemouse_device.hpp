// devices/spacemouse_device.hpp - a 6-DOF 3D mouse through spacenavd: rate control of the stylus pose.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "devices/haptic_device.hpp"

namespace tridex::devices {

/// Where spacenavd listens by default (its AF_UNIX socket; libspnav's SPNAV_SOCK_PATH).
inline constexpr const char* kSpnavDefaultSocket = "/var/run/spnav.sock";
/// spacenavd's configuration file, where a user may move its socket (`socket = PATH`).
inline constexpr const char* kSpnavConfigFile = "/etc/spnavrc";

/// The socket path a spacenavd configuration file sets: the value of its first `socket = PATH` line (leading and
/// trailing blanks dropped; blank lines and lines starting with '#' skipped), as libspnav's spnav_open reads
/// /etc/spnavrc (FreeSpacenav/libspnav, src/spnav.c, 2022). "" when the file cannot be read or sets none.
std::string spnav_socket_from_config(const std::string& config_path);

/// Where the spacemouse driver connects, in libspnav's order: `serial` (a scene's device.serial) when not empty,
/// else `env` ($SPNAV_SOCKET) when not empty, else the `socket` of the configuration file at `config_path`, else
/// spacenavd's default kSpnavDefaultSocket.
std::string spnav_socket_path(const std::string& serial, const std::string& env, const std::string& config_path);

/// Whether spacenavd answers at `socket_path` now: connects and closes at once. Returns "" when it does, else one
/// line: "no spacenavd at PATH (is the daemon running? Debian package spacenavd)" or the connect error.
std::string spnav_reachable(const std::string& socket_path);

/// How a SpaceMouseDevice turns the puck's deflection into motion (SI units).
struct SpaceMouseParams {
    std::string socket_path = kSpnavDefaultSocket;  ///< spacenavd's AF_UNIX socket
    double full_scale = 350.0;     ///< axis value at full deflection, device counts (> 0); larger values are clamped
    double dead_zone = 0.05;       ///< fraction of full_scale below which an axis reads as zero, [0, 1)
    double max_speed_m_s = 0.1;    ///< tip speed at full deflection of a translation axis, m/s (> 0)
    double max_rate_rad_s = 1.5;   ///< angular rate at full deflection of a rotation axis, rad/s (> 0)
};

/// Buttons spacenavd numbers, 0..kSpnavMaxButtons-1 (its MAX_BUTTONS, src/cfgfile.h, FreeSpacenav/spacenavd at
/// bac572a: a `bnmapN = M` line of /etc/spnavrc may send any button as number M up to 63).
inline constexpr int kSpnavMaxButtons = 64;

/// The spacenavd event stream decoded: one packet is 8 native int32 (spacenavd's send_uevent in src/proto_unix.c
/// and libspnav's proto.h, protocol v0): [0] type (0 motion, 1 press, 2 release, 3 device, 4 config, 5 raw axis,
/// 6 raw button); motion: [1..6] x, y, z, rx, ry, rz, [7] period (ms); press/release: [1] button number,
/// [2] 1 pressed / 0 released.
struct SpnavPacket {
    enum class Kind : std::uint8_t { kMotion, kPress, kRelease, kOther, kMalformed };
    Kind kind = Kind::kMalformed;
    std::array<int, 6> axes{};  ///< kMotion: x, y, z, rx, ry, rz, device counts
    int button = 0;             ///< kPress / kRelease: button number, 0..kSpnavMaxButtons-1
};

/// Decodes one 32-byte packet; a type outside 0..6, a button outside 0..kSpnavMaxButtons-1 or an axis beyond
/// +-32767 is kMalformed (dropped by the device). Never throws.
SpnavPacket decode_spnav_packet(const std::array<std::int32_t, 8>& words);

/// A HapticDevice reading a 3D mouse (SpaceNavigator, SpaceMouse) from spacenavd's AF_UNIX socket, speaking
/// its event protocol directly (see SpnavPacket). Rate control: each read() (one loop period dt) drains the
/// socket without blocking, then moves the tip at velocity = max_speed_m_s * a (a = the newest translation
/// axes / full_scale, clamped to [-1, 1], dead zone removed and rescaled) and turns the stylus at angular rate
/// max_rate_rad_s * the rotation axes likewise (device frame: spacenavd's x, y, rx, ry as reported, its z and rz
/// negated, since spacenavd's frame is left-handed with z into the screen and the device frame is right-handed
/// with z toward the viewer, as libspnav's spnav_posrot_moveobj converts them, src/util.c); the tip is
/// clamped to the profile's workspace. Buttons: every button spacenavd numbers (0..63) is kept; DeviceState::buttons
/// carries buttons 0..31 (bit i = spacenavd button i, button 0 = the stylus button) and all_buttons() all 64.
/// Forces are ignored (a 3D mouse renders none; write() still gates and bounds them). A daemon that closes
/// the socket raises kFaultVanished: the pose is held, the buttons released, and read() goes on returning it.
class SpaceMouseDevice : public HapticDevice {
public:
    /// `profile`: the limits the loop applies (workspace, forces); `start_m`: the tip before any motion,
    /// device frame, m; dt_s: the loop period, s. Throws tridex::Error when dt_s is not in (0, 1], start_m is
    /// not finite or a parameter is out of range.
    SpaceMouseDevice(DeviceProfile profile, const Vec3& start_m, double dt_s, SpaceMouseParams params = {});
    ~SpaceMouseDevice() override;

    const DeviceProfile& profile() const override { return profile_; }
    /// exchanges = reads, missed_frames = reads after the daemon vanished, malformed_frames = dropped packets.
    DeviceLinkStats link_stats() const override { return stats_; }
    /// Every button held at the last read(): bit i = spacenavd button i, 0..63 (DeviceState::buttons has 0..31).
    std::uint64_t all_buttons() const { return reported_buttons_; }

protected:
    /// Connects to the socket; throws tridex::Error "spacemouse: no spacenavd at PATH: is the daemon running?
    /// (Debian package spacenavd)" when nothing listens there.
    void on_open() override;
    void on_close() noexcept override;
    /// Drains pending packets (bounded), integrates one step of dt; true unless never opened.
    bool do_read(DeviceState& out) override;
    void do_write(const Vec3& force_n, const Vec3& torque_nm) override;

private:
    void drain();
    void apply(const SpnavPacket& p);
    double shaped(int counts) const;

    DeviceProfile profile_;
    double dt_;
    SpaceMouseParams params_;
    int fd_ = -1;
    bool vanished_ = false;
    std::array<unsigned char, 32> partial_{};
    std::size_t have_ = 0;
    std::array<int, 6> axes_{};
    std::uint64_t buttons_ = 0;           // as the packets left them
    std::uint64_t reported_buttons_ = 0;  // as the last read() reported them
    Pose pose_;
    std::uint64_t steps_ = 0;
    DeviceLinkStats stats_;
};

}  // namespace tridex::devices
