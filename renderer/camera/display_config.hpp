// renderer/camera/display_config.hpp - the display a session shows on: screen corners, stereo output, eyes, rate.
#pragma once

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "core/math.hpp"
#include "core/pose.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/camera/stereo_output_mode.hpp"

namespace tridex::renderer {

/// Everything about the physical display that the renderer needs (SI units). The screen is given, as VR
/// Juggler and Vrui describe screens, by three corners in tracker space (m).
///
/// JSON form (every field optional; missing fields take the values of `preset`; unknown fields are refused):
/// ```
/// { "preset": "desktop" | "powerwall",
///   "screen": "desktop-monitor" | "powerwall" |
///             {"lower_left": [x, y, z], "lower_right": [x, y, z], "upper_left": [x, y, z]},   // m
///   "stereo": "frame-sequential",        // a name of parse_stereo_output
///   "anaglyph": "dubois",                // "dubois" | "colour" | "gray"
///   "eye_separation_m": 0.064,
///   "swap_eyes": false,
///   "ambient_occlusion": true,           // shade cuts darker and edges brighter (SceneView::occlusion_strength)
///   "refresh_hz": 120,
///   "resolution": [1280, 960],           // pixels, per eye image
///   "default_head_m": [0, 0, 2],         // head position when no tracker drives it, m
///   "tracking": {                        // head tracking (e.g. ART DTrack); both transforms default to identity
///     "tracker_to_wall": {"position_m": [x, y, z], "orientation_wxyz": [w, x, y, z]},
///     "head_to_eyes":    {"position_m": [x, y, z], "orientation_wxyz": [w, x, y, z]} } }
/// ```
/// The world of a session is the frame the screen corners are given in ("wall" coordinates). With identity
/// tracking transforms the corners are measured in tracker coordinates (e.g. by touching them with a tracked
/// pointer); otherwise tracker_to_wall maps tracker coordinates into the corners' frame.
/// The eye separation every tridex view uses unless a display config says otherwise, m: about the adult mean
/// interpupillary distance (63-64 mm; Dodgson, "Variation and extrema of human interpupillary distance", 2004).
inline constexpr double kDefaultEyeSeparationM = 0.064;

struct DisplayConfig {
    Screen screen = Screen::desktop_monitor();      ///< corners in tracker space, m
    StereoOutput stereo = StereoOutput::kMono;       ///< how the two eyes reach the viewer
    AnaglyphMethod anaglyph = AnaglyphMethod::kDubois;  ///< mixing for StereoOutput::kAnaglyph
    double eye_separation_m = kDefaultEyeSeparationM;  ///< interpupillary distance, m, 0..0.2
    bool swap_eyes = false;                          ///< exchange left and right on the display
    /// Screen-space ambient occlusion of the workpiece (renderer/stereo/ambient_occlusion.hpp): cuts darker, edges
    /// brighter; false saves its cost on a slow device.
    bool ambient_occlusion = true;
    double refresh_hz = 60.0;                        ///< display refresh, Hz, (0, 1000]
    int width_px = 1920;                             ///< per-eye image width, pixels, 1..16384
    int height_px = 1080;                            ///< per-eye image height, pixels, 1..16384
    /// The config named its resolution. A desk window then opens at that size (shrunk to fit the monitor); without
    /// one it opens sized to the monitor it opens on, and the window's size decides the eye images' size.
    bool resolution_given = false;
    Vec3 default_head_m{0.0, 0.0, 0.6};              ///< head position without a tracker, m, in front of the screen
    /// Rigid calibration from tracker coordinates (m) to the screen corners' frame: p_wall = apply(p_tracker).
    Pose tracker_to_wall;
    /// The tracked head body's frame -> the head frame the eyes use (origin midway between the eyes, +x to the
    /// right eye, +y up, +z backwards): head = body * head_to_eyes. E.g. a glasses target 8 cm above and 2 cm in
    /// front of the eyes, axes aligned: position_m (0, -0.08, 0.02).
    Pose head_to_eyes;

    /// The paper's PowerWall: Screen::powerwall() (10 ft x 7.5 ft), frame-sequential at 120 Hz (60 Hz per eye),
    /// 1280 x 960 per eye (4:3 like the screen), eye separation kDefaultEyeSeparationM, head 2 m in front of the centre.
    static DisplayConfig powerwall();
    /// A desk: Screen::desktop_monitor() (0.53 m x 0.30 m), mono (anaglyph by choice: red-cyan glasses are rare at a
    /// desk, and it costs a second eye), 60 Hz, 1920 x 1080 offscreen (a window: sized to the monitor),
    /// eye separation kDefaultEyeSeparationM, head 0.6 m in front of the centre. Same as a default-constructed DisplayConfig.
    static DisplayConfig desktop();
};

/// Checks every field of `config` (the ranges documented on DisplayConfig; the screen corners must be finite,
/// non-degenerate and at a right angle at lower_left within |cos| <= 1e-6; the default head must be in front
/// of the screen; the tracking transforms finite with unit orientations within 1e-6). Throws tridex::Error "<source>: field '<name>': <what is wrong>" for the first bad field.
void validate_display_config(const DisplayConfig& config, const std::string& source);

/// Reads a DisplayConfig from parsed JSON (form above). Screen corners that are a little off a right angle
/// (measured corners; |cos| <= 0.01, i.e. about 0.6 degrees) are squared up by removing from the up edge its
/// component along the right edge (upper_left moves within the screen plane); larger errors are refused.
/// `source` names the file in messages. Throws tridex::Error "<source>: field '<name>': ..." for a wrong type,
/// an out-of-range or non-finite value, an unknown name or an unknown field.
DisplayConfig display_config_from_json(const nlohmann::json& json, const std::string& source);

/// The JSON form of `config` (every field written, "preset" omitted). Throws like validate_display_config.
nlohmann::json display_config_to_json(const DisplayConfig& config);

/// Loads a display config file (JSON). Throws tridex::Error naming `path` when the file cannot be read, is not
/// valid JSON (with the parser's position), or a field is bad (see display_config_from_json).
DisplayConfig load_display_config(const std::string& path);

/// Writes `config` to `path` as indented JSON. Throws tridex::Error naming `path` when a field is invalid
/// (validate_display_config) or the file cannot be written.
void save_display_config(const std::string& path, const DisplayConfig& config);

}  // namespace tridex::renderer
