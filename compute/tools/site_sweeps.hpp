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

/// Per-site state of an interleaved tool sample stream. Each site's previous sample starts its next sweep, so two
/// people carving at once never join their tools; the one open stroke belongs to the site whose sweeps opened it.
/// When another site's sample would sweep (it cuts and that site has a previous sample), the open stroke closes first
/// (StrokeClose::kSiteSwitch): its site's gesture is then "interrupted", and the next stroke of that site continues it
/// (continues()). With one site (every sample site 0) the rules are the single tool's: a stroke closes where the tool
/// stops cutting or changes (sample_closes_stroke). Not thread-safe.
class SiteSweeps {
public:
    /// Whether the open stroke closes before `s` is applied; `stroke_open`: the caller has an open stroke (or sweeps
    /// of one not applied yet). Throws tridex::Error when s.site >= kMaxSites.
    StrokeClose closes_before(const ToolSample& s, bool stroke_open) const;
    /// Appends to `out` the sweeps from s's site's previous sample to `s` (sample_sweeps; none for the site's first
    /// sample or a sample that does not cut), makes `s` that site's previous sample, and returns the number appended.
    /// A sweep appended makes s's site the open stroke's. `mesh` and `mirrored_mesh` as sample_sweeps. Throws
    /// tridex::Error when s.site >= kMaxSites, or as sample_sweeps.
    std::size_t advance(const ToolSample& s, std::shared_ptr<const MeshTool> mesh,
                        const std::shared_ptr<const MeshTool>& mirrored_mesh, const Vec3& centre_m,
                        std::vector<Sweep>& out);
    /// Call when the open stroke closed (for any reason): `by_site`, the site of the sample that closed it with
    /// kSiteSwitch (its site's gesture is interrupted and goes on), or nullopt (its gesture ended).
    void stroke_closed(std::optional<std::uint8_t> by_site = std::nullopt);
    /// The site whose sweeps opened the open stroke (the newest site that swept).
    std::uint8_t open_site() const { return open_site_; }
    /// When `site`'s gesture was interrupted by another site's stroke and has not ended since: the site that
    /// interrupted it most recently; nullopt otherwise. A stroke that `site` opens now continues that gesture.
    std::optional<std::uint8_t> interrupted_by(std::uint8_t site) const;
    /// `site`'s previous sample (nullptr before its first).
    const ToolSample* prev(std::uint8_t site) const;
    /// Sets `site`'s previous sample (a replay that resumes after a checkpoint). Throws tridex::Error when
    /// s.site >= kMaxSites.
    void set_prev(const ToolSample& s);

private:
    static void check(const ToolSample& s);
    std::array<std::optional<ToolSample>, kMaxSites> prev_{};
    std::array<std::optional<std::uint8_t>, kMaxSites> interrupted_by_{};
    std::uint8_t open_site_ = 0;
};

}  // namespace tridex::compute
