// haptics/recent_cuts.hpp - the subtracting tool's own recent sweeps, taken as cut before the snapshot shows them.
#pragma once

#include <array>
#include <cstdint>

#include "core/active_surface.hpp"
#include "core/math.hpp"
#include "core/tool_sample.hpp"

namespace tridex::haptics {

/// Removes the part of the solid interval [enter, exit] of one ray that a capsule covers, in place on a window's ray
/// (ActiveSurface::Window, window-local ray (iu, iv)): the capsule's chord [c0, c1] (grid units along the ray) is
/// taken out of every interval, splitting one in two where it lies inside; intervals left shorter than 1e-6 cells
/// vanish. A ray that would hold more than ActiveSurface::kMaxIntervals intervals keeps those nearest the chord's
/// middle and is marked truncated. c0 > c1 (or a NaN) changes nothing. Returns true when the ray changed.
bool cut_ray(ActiveSurface::Window& w, int iu, int iv, double c0, double c1);

/// The chord of a ray with a capsule, in grid units: the ray of set `axis` (0..2) through grid point (u, v) (along
/// axis (axis+1)%3 and (axis+2)%3), the capsule of radius r (cells, > 0) about the segment a..b (grid coordinates):
/// core/capsule_chord.hpp's chord in double. Returns true and the depths [t0, t1] along the axis when the ray meets
/// it, false when it misses (or on an axis outside 0..2, r <= 0 or a NaN).
bool ray_capsule_chord(int axis, double u, double v, const Vec3& a, const Vec3& b, double r, double& t0, double& t1);

/// The sweeps of a subtracting ball tool (ToolOp::kSubtract) that the haptic loop sent and the sculpt thread may not
/// have applied yet. While carving, the snapshot the contact reads (published after the sculpt thread applied what it
/// drained) is tens of milliseconds older than the hand, so it still holds material the tool has cut; the proxy would
/// stand on it, left behind a HIP that is in free space. The loop records each carving sweep it pushes (a capsule from
/// the sample pushed before to this one, as the sculpt thread sweeps it, compute/tools/sample_sweep.hpp), and before
/// each contact update subtracts from a copy of the snapshot the sweeps made after the newest sample that snapshot
/// holds (ActiveSurface::applied_made_s): the contact then reads the model as it will be once the sculpt thread
/// catches up, as far as the tool's own cuts go (symmetric copies, other tools and other people's cuts are not
/// predicted; a flat-end or mesh tool is not recorded). Union, paint and the clay operations are never recorded.
/// At most kCapacity sweeps (the newest) are kept: a snapshot later than that by more than kCapacity carving ticks
/// shows the older ones late, as before. Nothing allocates or locks; the copy of the snapshot (about 111 KB) is made
/// only when a new snapshot comes while sweeps are pending, and each sweep tests only the rays under its bounds.
class RecentCuts {
public:
    static constexpr int kCapacity = 128;  ///< sweeps kept (ticks of carving at 1 kHz)

    /// One recorded sweep (world m, steady-clock s).
    struct Sweep {
        Vec3 from_m{0.0};     ///< ball centre at the previous pushed sample, m
        Vec3 to_m{0.0};       ///< ball centre at this sample, m
        double radius_m = 0;  ///< ball radius, m
        double made_s = 0;    ///< ToolSample::made_s of this sample, s
    };

    /// Forgets every sweep (a new session).
    void clear();
    /// Records the sweep of a pushed subtracting sample: the capsule of radius_m (m, > 0) from from_m to to_m
    /// (m), made at made_s (ToolSample::made_s, s, increasing from call to call). A non-finite value or a radius
    /// that is not > 0 is ignored (returns false).
    bool add(const Vec3& from_m, const Vec3& to_m, double radius_m, double made_s);
    /// Takes note of a sample the loop made, `pushed` when it went into the sculpt thread's ring: a pushed
    /// ToolOp::kSubtract sample of a ball tool (radius > 0) after an earlier pushed sample records the sweep from
    /// that sample to this one (add). Returns true when a sweep was recorded.
    bool note(const ToolSample& s, bool pushed);
    /// Sweeps kept now (<= kCapacity).
    int size() const { return count_; }

    /// The surface the contact should read: `snapshot` itself when no recorded sweep is newer than what it holds
    /// (or its applied_made_s is NaN, or it is empty), else `scratch` holding the snapshot with those sweeps
    /// subtracted. `scratch` must be the same object on every call (it is brought up to date incrementally while
    /// the snapshot's sequence and applied_made_s stay the same) and not be written by anyone else.
    const ActiveSurface& apply(const ActiveSurface& snapshot, ActiveSurface& scratch);

private:
    // Subtracts sweep s from every window of `out`.
    static void subtract(const Sweep& s, ActiveSurface& out);

    Vec3 last_pushed_m_{0.0};    // the position of the last sample pushed (where the sculpt thread sweeps from)
    bool have_last_pushed_ = false;
    std::array<Sweep, kCapacity> ring_{};
    int head_ = 0;            // index of the next write
    int count_ = 0;           // sweeps kept
    std::uint64_t added_ = 0; // sweeps ever added (the serial of the newest is added_)
    // What scratch holds: the snapshot's sequence and applied_made_s, and the serial of the newest sweep applied
    // (0 = scratch holds no copy).
    std::uint64_t scratch_sequence_ = 0;
    double scratch_applied_s_ = 0.0;
    std::uint64_t scratch_upto_ = 0;
};

}  // namespace tridex::haptics
