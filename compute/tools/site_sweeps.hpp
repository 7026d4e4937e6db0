// compute/tools/site_sweeps.hpp - the sweeps and stroke closes of a sample stream that interleaves the tools of
// several sites (a shared session): each site's sweeps join its own consecutive samples, and one stroke is open at a
// time, so another site's cut closes it. The sculpt thread and journal replay both follow these rules.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "compute/tools/mesh_tool.hpp"
#include "compute/tools/sweep.hpp"
#include "core/tool_sample.hpp"

namespace tridex::compute {

/// Why the open stroke closes before a sample (SiteSweeps::closes_before).
enum class StrokeClose : std::uint8_t {
    kNo,          ///< it stays open (or none is open)
    kGestureEnds, ///< the open stroke's own site stopped cutting or changed what it does (sample_closes_stroke)
    kSiteSwitch,  ///< another site's tool cuts: its sweep starts a stroke of that site; the closed one's gesture goes on
};

/// Sweep spacing: a cutting sample closer than this share of the tool radius to the sample the site's last sweep
/// ended at (its anchor) is not swept on its own; the next sweep starts at the anchor, and a stroke's close sweeps to
/// its last sample (SiteSweeps::finish_strokes), so the stroke ends exactly where the tool did. Between anchors the
/// path is taken straight: the swept volume differs from the sampled path's by at most the sagitta of the path over
/// one spacing, s^2 / (8 R) for a path bent to radius R. A brush's spacing in a sculpting program (Blender's sculpt
/// mode, 10 % of the radius by default) is the same idea.
inline constexpr double kSweepSpacingOfRadius = 0.1;
/// Spacing applies to tools at least this many cells of the model's lattice in radius: a smaller tool's sweep visits
/// few rays, and each of its samples is swept as it comes.
inline constexpr double kSweepSpacingMinRadiusCells = 16.0;

/// Whether `to` may be left unswept after `anchor` (the sample a site's last sweep ended at): both cut with the same
/// op, material, tool and symmetry (no stroke close between them); the op is a Boolean (subtract, union, paint; a clay
/// op's result depends on each step); the tool is a ball, or a flat end at the same orientation, at least
/// kSweepSpacingMinRadiusCells cells of `cell_m` in radius; and `to` lies within kSweepSpacingOfRadius of the radius of
/// the anchor. False when cell_m is not finite and > 0.
bool within_sweep_spacing(const ToolSample& anchor, const ToolSample& to, double cell_m);

/// Per-site state of an interleaved tool sample stream. Each site's anchor (the sample its last sweep ended at, or its
/// last sample that did not cut) starts its next sweep, so two people carving at once never join their tools; the one
/// open stroke belongs to the site whose sweeps opened it. Samples within the sweep spacing of the anchor are not swept
/// on their own (within_sweep_spacing); finish_strokes() sweeps to them when the stroke closes.
/// When another site's sample would sweep (it cuts and that site has a previous sample), the open stroke closes first
/// (StrokeClose::kSiteSwitch): its site's gesture is then "interrupted", and the next stroke of that site continues it
/// (continues()). With one site (every sample site 0) the rules are the single tool's: a stroke closes where the tool
/// stops cutting or changes (sample_closes_stroke). Not thread-safe.
class SiteSweeps {
public:
    /// Whether the open stroke closes before `s` is applied; `stroke_open`: the caller has an open stroke (or sweeps
    /// of one not applied yet). Throws tridex::Error when s.site >= kMaxSites.
    StrokeClose closes_before(const ToolSample& s, bool stroke_open) const;
    /// Appends to `out` the sweeps from s's site's anchor to `s` (sample_sweeps; none for the site's first sample, a
    /// sample that does not cut, or one within the sweep spacing of the anchor: within_sweep_spacing with `cell_m`,
    /// the model's cell size, m), makes `s` that site's previous sample (and its anchor unless it was left unswept), and
    /// returns the number appended. A sweep appended makes s's site the open stroke's. `mesh` and `mirrored_mesh` as
    /// sample_sweeps. Throws tridex::Error when s.site >= kMaxSites, or as sample_sweeps.
    std::size_t advance(const ToolSample& s, std::shared_ptr<const MeshTool> mesh,
                        const std::shared_ptr<const MeshTool>& mirrored_mesh, const Vec3& centre_m, double cell_m,
                        std::vector<Sweep>& out);
    /// Before the open stroke closes (for any reason): appends to `out` the sweep from each site's anchor to its last
    /// sample where that sample was left unswept, which then becomes the anchor. Returns the number appended. A sample
    /// is left unswept only after a sweep of its site since the last call, so with no stroke open nothing is, and every
    /// site's anchor is its previous sample. Throws as sample_sweeps.
    std::size_t finish_strokes(const Vec3& centre_m, std::vector<Sweep>& out);
    /// Call when the open stroke closed (for any reason): `by_site`, the site of the sample that closed it with
    /// kSiteSwitch (its site's gesture is interrupted and goes on), or nullopt (its gesture ended).
    void stroke_closed(std::optional<std::uint8_t> by_site = std::nullopt);
    /// The site whose sweeps opened the open stroke (the newest site that swept).
    std::uint8_t open_site() const { return open_site_; }
    /// When `site`'s gesture was interrupted by another site's stroke and has not ended since: the site that
    /// interrupted it most recently; nullopt otherwise. A stroke that `site` opens now continues that gesture.
    std::optional<std::uint8_t> interrupted_by(std::uint8_t site) const;
    /// `site`'s previous sample (nullptr before its first). Between strokes (checkpoints, snapshots) it is also the
    /// site's anchor.
    const ToolSample* prev(std::uint8_t site) const;
    /// Sets `site`'s previous sample and anchor (a replay that resumes after a checkpoint, a replica that joins
    /// between strokes). Throws tridex::Error when s.site >= kMaxSites.
    void set_prev(const ToolSample& s);

private:
    static void check(const ToolSample& s);
    std::array<std::optional<ToolSample>, kMaxSites> prev_{};
    std::array<std::optional<ToolSample>, kMaxSites> anchor_{};  // where the site's next sweep starts
    std::array<bool, kMaxSites> unswept_{};                       // prev_ cuts and was left unswept
    std::array<bool, kMaxSites> swept_{};  // the anchor ended a sweep since the last finish_strokes()
    std::array<std::optional<std::uint8_t>, kMaxSites> interrupted_by_{};
    std::uint8_t open_site_ = 0;
};

}  // namespace tridex::compute
