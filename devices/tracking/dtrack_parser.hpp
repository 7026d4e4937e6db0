// devices/tracking/dtrack_parser.hpp - ART DTrack ASCII UDP output: one datagram -> frame counter, timestamp,
// standard bodies and Flysticks (SI units), strictly checked.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/math.hpp"
#include "core/pose.hpp"

namespace tridex::devices {

/// Largest body or Flystick id the parser accepts (ids start at 0).
inline constexpr int kDTrackMaxId = 255;
/// Largest datagram the parser looks at, bytes (the largest UDP payload is 65507).
inline constexpr std::size_t kDTrackMaxDatagram = 65536;
/// Most Flystick buttons / controllers (joystick axes) per Flystick the parser accepts.
inline constexpr int kDTrackMaxButtons = 64;
inline constexpr int kDTrackMaxControllers = 16;

/// Why a datagram was rejected (each rejected datagram counts once, under the first fault found).
enum class DTrackReject : std::uint8_t {
    kNone = 0,     ///< accepted
    kEmpty,        ///< no line at all
    kTooLarge,     ///< longer than kDTrackMaxDatagram (or cut by the receive buffer)
    kNotText,      ///< a byte outside printable ASCII, tab, CR and LF (binary junk)
    kUnknownLine,  ///< an identifier that is not DTrack's (not lower-case letters and digits, or no values after it),
                   ///< or a datagram of unknown lines only
    kTruncated,    ///< a line ends in the middle of a value list or block
    kNotNumeric,   ///< a field that should be a number is not one
    kNotFinite,    ///< a number is NaN or infinite
    kSyntax,       ///< brackets or separators out of place, too many values in a block
    kBodyCount,    ///< a line's body count disagrees with its blocks, or with 6dcal / the defined Flysticks
    kOutOfRange,   ///< a value outside its documented range (quality, id, position, buttons, controllers)
    kNotRotation,  ///< a tracked body's 3x3 matrix is not a rotation (orthonormal, det +1, within 1e-3)
    kDuplicate,    ///< a line type or a body id appears twice in one datagram
    kReplayed,     ///< (receiver) a frame counter older than the newest accepted one: a late or replayed datagram
    kCount         ///< number of values (array sizes)
};
/// A short lower-case name ("truncated", "not_numeric", ...), as used in report.json.
const char* to_string(DTrackReject reason);

/// One 6DOF body of a `6d` line (or the pose part of a Flystick).
struct DTrackBody {
    int id = 0;                ///< DTrack id, 0..kDTrackMaxId
    double quality = -1.0;     ///< 0..1 when tracked; -1 when DTrack says the body is not tracked
    Vec3 position_m{0.0};      ///< body origin in tracker coordinates, m (DTrack sends mm)
    glm::dmat3 rotation{1.0};  ///< body -> tracker rotation (DTrack's b0..b8 are its columns, column-wise)
    /// True when DTrack tracked the body in this frame (quality >= 0).
    bool tracked() const { return quality >= 0.0; }
    /// The body pose in tracker coordinates (m; orientation from `rotation`, normalised).
    Pose pose() const;
};

/// One Flystick of a `6df2` line.
struct DTrackFlystick {
    DTrackBody body;                                          ///< pose and quality
    int button_count = 0;                                     ///< buttons the Flystick has, 0..kDTrackMaxButtons
    std::uint64_t buttons = 0;                                ///< bit i set: button i pressed
    int controller_count = 0;                                 ///< controllers (joystick axes), 0..kDTrackMaxControllers
    std::array<double, kDTrackMaxControllers> controllers{};  ///< each in [-1, 1]
};

/// What one datagram said. Fields a datagram did not carry keep their "absent" values.
struct DTrackFrame {
    bool has_frame_counter = false;
    std::uint32_t frame_counter = 0;  ///< `fr`: DTrack's frame counter
    bool has_timestamp = false;
    double timestamp_s = 0.0;  ///< `ts2`, else `ts`: seconds since 00:00 UTC (DTrack's clock, us resolution)
    bool has_latency = false;
    double latency_s = 0.0;                 ///< `ts2`: the tracker's own latency for this frame, s
    int calibrated_bodies = -1;             ///< `6dcal`: number of calibrated standard bodies; -1 when absent
    std::vector<DTrackBody> bodies;         ///< `6d`, in line order (untracked ones included when DTrack sends them)
    int flysticks_defined = -1;             ///< `6df2`: number of defined Flysticks; -1 when absent
    std::vector<DTrackFlystick> flysticks;  ///< `6df2`, in line order
    int ignored_lines = 0;                  ///< lines of other DTrack types (3d, gl, 6dmt, 6di, 6dj, st, ...) skipped
    /// Lines of a type tridex does not know (a later DTrack's), skipped as ART's DTrackSDK skips them.
    int unknown_lines = 0;
    /// Values after the ones tridex reads in id blocks ([id qu ...]), which a later DTrack may add; skipped.
    int extra_values = 0;
    /// Back to the empty frame; keeps the vectors' capacity (no allocation in steady state).
    void clear();
    /// The body with DTrack id `id`, or nullptr.
    const DTrackBody* body(int id) const;
};

/// Where a datagram failed: the reason and the 1-based line number (0 for whole-datagram faults).
struct DTrackParseResult {
    DTrackReject reason = DTrackReject::kNone;
    int line = 0;
    /// True when the datagram was accepted.
    bool ok() const { return reason == DTrackReject::kNone; }
};

/// Parses one DTrack ASCII datagram into `out` (cleared first), after the format of ART's "DTrack2 User's
/// Manual", section "Output of measurement data" / "Technical Appendix: ASCII format", as implemented by ART's
/// DTrackSDK (src/DTrackParser.cpp, ar-tracking/DTrackSDK v2.9.0, 110f7e5):
///   fr <frame counter>
///   ts <timestamp, s since 00:00 UTC>
///   ts2 <s since 1970> <us> <latency us>   (DTRACK3's extended timestamp; DTrackSDK's parseLine_ts2; when a
///        datagram carries both ts and ts2, ts2's time is used)
///   6dcal <number of calibrated standard bodies>
///   6d <n> [id qu][sx sy sz eta theta phi][b0 b1 b2 b3 b4 b5 b6 b7 b8] ... (n blocks; the location block may
///        carry only sx sy sz; eta theta phi, Euler angles in degrees, are checked but not used)
///   6df2 <defined> <n> [id qu nbt nct][sx sy sz][b0 ... b8][bt0 .. ct0 ..] ... (buttons as ceil(nbt/32)
///        32-bit bit fields, then nct controller values in [-1, 1])
/// Lines end with LF or CR LF; positions are mm (converted to m here); b0..b8 is the body -> tracker rotation
/// matrix column by column; quality -1 means "not tracked" (its pose is not checked). Other DTrack line
/// types (3d, 6dcov, 6df, 6di, 6dj, 6dmt, 6dmt2, 6dmtr, gl, glcal, st) are skipped and counted, and so are line
/// types tridex does not know whose identifier is DTrack-like (lower-case letters and digits: a later DTrack's),
/// as the SDK skips them; extra finite values at the end of an id block are skipped and counted too (the SDK
/// ignores additional data inside a block). Trailing NUL bytes (a C string's terminator) are dropped.
/// Otherwise strict: any fault rejects the whole datagram (returns its reason; `out` is then unspecified), and so
/// does a datagram of unknown lines only. Never throws for any input, never reads outside `datagram`. Cost:
/// linear in the datagram's length.
DTrackParseResult parse_dtrack_datagram(std::string_view datagram, DTrackFrame& out);

}  // namespace tridex::devices
