// devices/recording.hpp - a haptic session on disk: one record per loop tick (binary), a reader that
// validates everything, and a CSV export for analysis.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "core/atomic_file.hpp"
#include "core/crc32.hpp"
#include "core/math.hpp"
#include "core/symmetry.hpp"
#include "core/tool_shape.hpp"
#include "devices/haptic_device.hpp"

namespace tridex::devices {

/// What one haptic tick did, in SI units and the world frame unless stated. The fields after
/// `device` are the recorded data of Singapogu's MS thesis (Clemson 2007), chapter 3, Table 3 (wand
/// centre translation, rotation as axis-angle, the top and bottom wand points, their collision
/// points and deviations, the per-point and summed forces, the collision ids); `device`, `buttons`
/// and `tool_mode` are what a replay needs.
/// A one-point tool (a single HIP) records its point as top_* and sets bottom_* to the same point
/// with zero deviation and force and bottom_collision_id = -1.
/// Validity rules (RecordingWriter::write and read_recording enforce them, naming the field):
///   - t_s finite and strictly greater than the previous tick's t_s;
///   - valid is 0 or 1; tool_mode and op are ToolOp values (0..8: kPush 4, kSmooth 5, kPull 6, kGrab 7, kPlace 8);
///     tool.kind is a ToolKind value (0..2), tool.radius_m and tool.length_m finite and >= 0;
///   - valid == 1: every field of `device` is finite; valid == 0: `device` is recorded as the device
///     gave it (it may hold NaN or infinity, that is why the loop flagged it);
///   - all other vectors and scalars finite; rotation_axis unit length (within 1e-6);
///     rotation_angle_rad in [0, 2*pi]; deviations >= 0; collision ids >= -1.
struct RecordedTick {
    double t_s = 0.0;                    ///< tick time, s (device time when it advances, else the loop clock)
    DeviceState device;                  ///< the raw device sample (device frame) - the replay input
    Vec3 wand_centre_m{0.0};             ///< tool centre in the world, m (thesis: wand centre translation)
    Vec3 rotation_axis{1.0, 0.0, 0.0};   ///< unit axis of the tool rotation (see to_axis_angle)
    double rotation_angle_rad = 0.0;     ///< rotation angle about rotation_axis, rad, in [0, 2*pi]
    Vec3 top_m{0.0};                     ///< top wand point in the world, m
    Vec3 bottom_m{0.0};                  ///< bottom wand point in the world, m
    Vec3 top_contact_m{0.0};             ///< the top point's collision (proxy) point, m
    Vec3 bottom_contact_m{0.0};          ///< the bottom point's collision (proxy) point, m
    double top_deviation_m = 0.0;        ///< penetration depth of the top point, m (>= 0)
    double bottom_deviation_m = 0.0;     ///< penetration depth of the bottom point, m (>= 0)
    Vec3 top_force_n{0.0};               ///< force from the top point, N
    Vec3 bottom_force_n{0.0};            ///< force from the bottom point, N
    Vec3 force_n{0.0};                   ///< summed force sent to the device, world frame, N
    Vec3 torque_nm{0.0};                 ///< torque about the tool centre, N*m
    std::int32_t top_collision_id = -1;  ///< -1 = no contact, else the ray set / face id touched
    std::int32_t bottom_collision_id = -1;  ///< as top_collision_id, for the bottom point
    std::uint32_t buttons = 0;           ///< device button bits at the tick
    std::uint8_t tool_mode = 0;          ///< the ToolOp value in effect (core/tool_sample.hpp)
    std::uint8_t valid = 1;              ///< 0 when the device sample was invalid (loop sent zero force)
    /// The ToolOp selected at the tick (keys at the desk change it), before engagement and pauses; version 1
    /// files: tool_mode.
    std::uint8_t op = 0;
    std::uint8_t material = 0;           ///< the material selected at the tick (what union adds, paint sets)
    /// The tool the tick's sample carried (kind, radius_m, length_m; mesh_id is not stored): its size changes
    /// with keys at the desk. radius_m 0 = not recorded (version 1 files, invalid ticks): the session's tool.
    ToolShape tool{};
    /// The symmetry the tick's sample carried (core/symmetry.hpp; keys and the menu at the desk change it); off in
    /// files before version 3.
    Symmetry symmetry{};
    /// The workpiece the tick's sample carved (0..kMaxRecordedWorkpieces-1: the haptic loop's target, which a replay
    /// takes from here rather than from its own contacts); -1 = not recorded (files before version 4).
    int workpiece = -1;
};

/// A point in a recorded session's stream of tool samples where the sculpt thread took a request whose timing the
/// samples do not carry: an undo, a redo or a stroke close (the sculpt thread's SculptMark).
struct RecordedMark {
    std::uint64_t after_samples = 0;  ///< tool samples the sculpt thread had taken before it
    std::string kind;                 ///< "undo", "redo", "end_stroke", "finer" or "coarser" (a coarseness change)
    /// The workpiece whose sculpt thread made it (0..kMaxRecordedWorkpieces-1; every workpiece's thread takes every
    /// sample, so after_samples counts alike for all). 0 in files written before sessions held several.
    std::uint8_t workpiece = 0;
};

/// A workpiece's pose set during a recorded session (the undo or redo of a placement; the haptic loop's PoseChange):
/// a replay sets it at the first tick from `tick` on with a finite sample on which the tool holds no workpiece.
struct RecordedPose {
    std::uint64_t tick = 0;      ///< the tick that took it (0-based index into the ticks; never decreasing in a list)
    double device_t_s = 0.0;     ///< that tick's device time, s (finite; for people reading the file)
    std::uint8_t workpiece = 0;  ///< 0..kMaxRecordedWorkpieces-1
    Pose pose{};                 ///< model frame -> world from then on (m; finite, unit quaternion)
};

/// The session-wide part of a recording.
struct RecordingHeader {
    std::string device_name;     ///< DeviceProfile::name of the recorded device (the replay picks its profile)
    double period_s = 1e-3;      ///< haptic loop period, s (finite, > 0)
    std::string workspace_mode;  ///< workspace technique of the session ("moving", "scaling", "clutching", "bubble", ...)
    std::string notes;           ///< free text the app fills (mesh, resolution, tool radius, ...); any UTF-8
    /// The session's undos, redos and stroke closes in order (after_samples never decreasing); absent in files
    /// written before they were recorded (a replay then closes strokes by itself and undoes nothing).
    std::optional<std::vector<RecordedMark>> marks;
    /// The in-scene menu's track (the app's JSON array of what the menu showed and when, app/menu/menu_frame.hpp),
    /// so that a replay shows the same menu; "" = none (sessions without a menu, older files).
    std::string menu;
    /// The workpieces' pose sets in order (empty in files that have none: header key "poses", absent then).
    std::vector<RecordedPose> poses;
};

/// A recording in memory.
struct Recording {
    RecordingHeader header;
    std::vector<RecordedTick> ticks;  ///< in time order
};

// ---- File format "TRDXREC", version 2 (version 1 is still read) --------------------------------------
// Every number is little-endian; doubles are IEEE-754 binary64, stored bit for bit.
//   Preamble, 32 bytes:
//     0  char[8]  magic "TRDXREC\0"
//     8  u32      version (2; 1 in older files)
//    12  u32      bytes per tick record (397; 378 in version 1)
//    16  u64      tick count (0xFFFFFFFFFFFFFFFF while the writer is open: such a file is refused)
//    24  u32      CRC-32 (IEEE 802.3, as zlib/PNG) of the header text followed by all tick records
//    28  u32      header text length L, bytes
//   Header text, L bytes at 32: UTF-8 JSON object {"device_name": string, "period_s": number,
//     "workspace_mode": string, "notes": string, optional "marks": [{"after_samples": integer >= 0,
//     "kind": "undo" | "redo" | "end_stroke"}, ...] (after_samples never decreasing), optional "menu": [...] (the
//     app's menu track), optional "poses": [{"tick": integer >= 0, "t_s": number, "workpiece": integer,
//     "position_m": [x, y, z], "orientation": [w, x, y, z]}, ...] (RecordedPose; tick never decreasing)} (other
//     keys are ignored).
//   Tick records, 402 bytes each (version 1: 378, ending at `valid`; version 2: 397, ending at the tool length;
//   version 3: 401, ending at the symmetry),
//   from byte 32 + L; offsets within a record:
//       0 t_s f64 | 8 device.t_s f64 | 16 device position xyz f64 | 40 device orientation w,x,y,z f64
//      72 device velocity xyz f64 | 96 device buttons u32 | 100 wand_centre xyz | 124 rotation_axis xyz
//     148 rotation_angle f64 | 156 top xyz | 180 bottom xyz | 204 top_contact xyz | 228 bottom_contact xyz
//     252 top_deviation f64 | 260 bottom_deviation f64 | 268 top_force xyz | 292 bottom_force xyz
//     316 force xyz | 340 torque xyz | 364 top_collision_id i32 | 368 bottom_collision_id i32
//     372 buttons u32 | 376 tool_mode u8 | 377 valid u8
//     version 2 adds: 378 op u8 | 379 material u8 | 380 tool kind u8 | 381 tool radius f64 | 389 tool length f64
//     version 3 adds: 397 symmetry u32 (core/symmetry.hpp symmetry_bits: mirror bits | radial axis << 8
//     | radial copies << 16)
//     version 4 adds: 401 workpiece u8 (the workpiece the tick carved, 0..7)
// ----------------------------------------------------------------------------------------------------

inline constexpr char kRecordingMagic[8] = {'T', 'R', 'D', 'X', 'R', 'E', 'C', '\0'};  ///< first 8 bytes
inline constexpr std::uint32_t kRecordingVersion = 4;        ///< the version this build writes (it reads 1 to 4)
inline constexpr std::size_t kRecordingPreambleBytes = 32;   ///< bytes before the header text
inline constexpr std::size_t kRecordedTickBytes = 402;       ///< bytes per tick record on disk (version 4)
inline constexpr std::size_t kRecordedTickBytesV3 = 401;     ///< bytes per tick record of version 3 files
/// Most workpieces a recorded session may have had (RecordedTick::workpiece; the haptic loop's kMaxLoopWorkpieces).
inline constexpr int kMaxRecordedWorkpieces = 8;
inline constexpr std::size_t kRecordedTickBytesV2 = 397;     ///< bytes per tick record of version 2 files
inline constexpr std::size_t kRecordedTickBytesV1 = 378;     ///< bytes per tick record of version 1 files

/// The recording's checksum: tridex::crc32_ieee (core/crc32.hpp), named here too for the recording's users.
using tridex::crc32_ieee;

/// Unit axis and angle (rad, in [0, pi]) of the rotation q (normalised first). The identity, or a
/// rotation whose angle is below 1e-12 rad, gives axis +x and angle 0. Non-finite or zero q gives
/// axis +x and angle NaN (such a tick cannot be recorded).
void to_axis_angle(const Quat& q, Vec3& axis_out, double& angle_rad_out);

/// Checks one tick against the validity rules of RecordedTick. `previous_t_s` is the t_s of the tick
/// before it (NaN for the first tick). Returns an empty string when valid, else one phrase naming the
/// field, e.g. "top_deviation_m = -0.001 is negative".
std::string check_tick(const RecordedTick& tick, double previous_t_s);

/// Writes a recording tick by tick (after the session, from the loop's records: it allocates and does
/// file I/O, so never call it from the 1 kHz thread).
/// The bytes go to a temporary file (core/atomic_file.hpp: unnamed where the file system allows) that close()
/// renames over `path`, so `path` holds the previous file or the whole new recording, never a cut one. The
/// destructor closes too, except during stack unwinding (an exception in flight), when it discards the temporary
/// file and leaves `path` as it was; errors in the destructor are swallowed, call close() to see them. Not
/// thread-safe.
class RecordingWriter {
public:
    /// Opens the temporary file for `path` and writes the preamble and header text.
    /// Throws tridex::Error "<path>: ..." when the file cannot be created or written, or the header is
    /// bad (period_s not finite or <= 0, a string that is not valid UTF-8).
    RecordingWriter(const std::string& path, const RecordingHeader& header);
    ~RecordingWriter();
    RecordingWriter(const RecordingWriter&) = delete;
    RecordingWriter& operator=(const RecordingWriter&) = delete;

    /// Appends one tick. Throws tridex::Error "<path>: tick <i>: <what>" when it breaks a rule of
    /// RecordedTick (nothing is written then), or on a write error or after close().
    void write(const RecordedTick& tick);
    /// Writes the tick count and checksum and renames the file over `path`. Idempotent.
    /// Throws tridex::Error "<path>: ..." on a write error.
    void close();
    /// Ticks written so far.
    std::size_t ticks_written() const { return count_; }

private:
    std::string path_;
    std::optional<AtomicFile> atomic_;  // the temporary file until close() commits it; empty once closed
    std::uint32_t crc_ = 0;
    std::size_t count_ = 0;
    double last_t_s_;
    int uncaught_at_open_ = 0;
};

/// Writes a whole recording with RecordingWriter (same errors).
void write_recording(const std::string& path, const Recording& recording);

/// Reads and validates a recording (version 2, or version 1, whose ticks get op = tool_mode, material 0 and no
/// tool). Throws tridex::Error naming the path and, where it applies, the
/// byte offset or tick index: unreadable file, wrong magic, another version, another tick size,
/// truncated or unfinished file, trailing bytes, bad header JSON or header field, a tick breaking a
/// rule of RecordedTick (NaN where not allowed, time not increasing, ...), checksum mismatch.
Recording read_recording(const std::string& path);

/// Writes the recording as CSV for analysis: one header row of named columns, then one row per tick,
/// numbers printed with 17 significant digits (they read back to the same doubles; NaN as "nan").
/// Columns: t_s, device_t_s, device_x_m, device_y_m, device_z_m, device_qw, device_qx, device_qy,
/// device_qz, device_vx_m_s, device_vy_m_s, device_vz_m_s, device_buttons, then the thesis Table 3
/// fields wand_centre_{x,y,z}_m, rotation_axis_{x,y,z}, rotation_angle_rad, top_{x,y,z}_m,
/// bottom_{x,y,z}_m, top_collision_{x,y,z}_m, bottom_collision_{x,y,z}_m, top_deviation_m,
/// bottom_deviation_m, top_force_{x,y,z}_n, bottom_force_{x,y,z}_n, force_{x,y,z}_n,
/// torque_{x,y,z}_nm, top_collision_id, bottom_collision_id, then buttons, tool_mode, valid, op, material,
/// tool_kind, tool_radius_m, tool_length_m.
/// Throws tridex::Error "<path>: ..." when the file cannot be written.
void write_recording_csv(const std::string& path, const Recording& recording);

/// The CSV column names of write_recording_csv, in order.
const std::vector<std::string>& recording_csv_columns();

}  // namespace tridex::devices
