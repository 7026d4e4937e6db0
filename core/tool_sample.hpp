// core/tool_sample.hpp - what the haptic thread tells the sculpt thread each tick.
#pragma once

#include <cstdint>
#include <limits>

#include "core/math.hpp"
#include "core/symmetry.hpp"
#include "core/tool_shape.hpp"

namespace tridex {

/// What the tool does to material along its swept volume.
enum class ToolOp : std::uint8_t {
    kNone = 0,      ///< touch only, no change
    kSubtract = 1,  ///< carve: remove the swept volume
    kUnion = 2,     ///< add the swept volume as material
    kPaint = 3,     ///< set a material id where the tool touches
    kPush = 4,      ///< clay: dent the pressed surface, its volume back as a rim (compute/tools/clay_push.hpp)
    kSmooth = 5,    ///< clay: relax the surface under the tool, keeping the volume (compute/tools/clay_smooth.hpp)
    kPull = 6,      ///< clay: the touched surface follows the tool outward, its volume taken from a moat (clay_push.hpp)
    kGrab = 7,      ///< clay: the material near the grabbed point moves with the tool, with a falloff (clay_grab.hpp)
    /// The whole workpiece follows the tool while it is engaged (its pose: haptics::HapticLoop), nothing carved: a
    /// mode of the haptic loop, never carried by a ToolSample (the samples carry kNone meanwhile).
    kPlace = 8,
};

/// The operation's name on the command line and in reports: "none", "subtract", "union", "paint", "push", "smooth",
/// "pull", "grab", "place".
inline const char* tool_op_name(ToolOp op) {
    switch (op) {
        case ToolOp::kNone: return "none";
        case ToolOp::kSubtract: return "subtract";
        case ToolOp::kUnion: return "union";
        case ToolOp::kPaint: return "paint";
        case ToolOp::kPush: return "push";
        case ToolOp::kSmooth: return "smooth";
        case ToolOp::kPull: return "pull";
        case ToolOp::kGrab: return "grab";
        case ToolOp::kPlace: return "place";
    }
    return "unknown";
}

/// Largest material id: 0 is the workpiece's own material, 1..kMaxMaterialId the palette that union adds and paint
/// sets (renderer/scene/material_palette.hpp draws ids 0..kMaxMaterialId).
inline constexpr std::uint8_t kMaxMaterialId = 7;

/// Most sites (people, each with their own tool) one session's sample stream holds: ToolSample::site is
/// 0..kMaxSites-1. Site 0 is the session's own (the host's) tool.
inline constexpr std::uint8_t kMaxSites = 16;

/// One tool pose in world space, pushed by the haptic loop through an SpscRing.
/// Consecutive samples form the swept segments the sculpt thread applies, in order.
struct ToolSample {
    double t_s = 0.0;                        ///< loop time of the sample, s
    Vec3 position{0.0};                      ///< tool centre (HIP), world m
    /// Where the active-surface window belongs, world m: the tool centre moved by contact point 0's
    /// proxy offset (proxy - point), so the window follows the god-object on the surface even when the
    /// hand pushes the HIP deep into material; = position when free. NaN (the default) = use position.
    Vec3 surface_m{std::numeric_limits<double>::quiet_NaN()};
    Quat orientation{1.0, 0.0, 0.0, 0.0};    ///< tool frame -> world
    ToolShape tool{};                        ///< the tool that cuts along the sweep ending here (tool frame: core/tool_shape.hpp)
    ToolOp op = ToolOp::kNone;               ///< Boolean (or clay operation) applied along the sweep ending here
    std::uint8_t material = 0;               ///< material id the union adds or the paint sets (kUnion, kPaint)
    std::uint32_t buttons = 0;               ///< device button bits at the sample
    /// The symmetric copies of the sweep ending here that the sculpt thread applies too, in the same batch, about the
    /// workpiece lattice's centre (compute/tools/symmetry.hpp). Off by default.
    Symmetry symmetry{};
    /// The site whose tool made the sample (0..kMaxSites-1; 0 = the session's own tool): a shared session's stream
    /// interleaves the samples of several tools, and a sweep joins two consecutive samples of the same site
    /// (compute/tools/site_sweeps.hpp).
    std::uint8_t site = 0;
    /// When the haptic loop made the sample: std::chrono::steady_clock time, s since its epoch; NaN when unknown
    /// (a journal or a recording read back). For latency figures only: never journalled, never affects the model.
    double made_s = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace tridex
