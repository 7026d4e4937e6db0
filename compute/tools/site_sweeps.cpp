// compute/tools/site_sweeps.cpp - per-site sweeps and stroke closes of an interleaved sample stream.
#include "compute/tools/site_sweeps.hpp"

#include <cmath>
#include <string>

#include "compute/tools/sample_sweep.hpp"
#include "core/error.hpp"

namespace tridex::compute {

namespace {
bool cuts(const ToolSample& s) { return s.op != ToolOp::kNone && s.tool.radius_m > 0.0; }
}  // namespace

bool within_sweep_spacing(const ToolSample& anchor, const ToolSample& to, double cell_m) {
    if (!(std::isfinite(cell_m) && cell_m > 0.0) || sample_closes_stroke(anchor, to)) return false;
    if (to.op != ToolOp::kSubtract && to.op != ToolOp::kUnion && to.op != ToolOp::kPaint) return false;
    const double r = to.tool.radius_m;
    if (!(r >= kSweepSpacingMinRadiusCells * cell_m)) return false;
    if (to.tool.kind == ToolKind::kMesh) return false;
    if (to.tool.kind != ToolKind::kBall && !(to.orientation == anchor.orientation)) return false;
    const Vec3 d = to.position - anchor.position;
    const double spacing = kSweepSpacingOfRadius * r;
    return glm::dot(d, d) < spacing * spacing;
}

void SiteSweeps::check(const ToolSample& s) {
    if (s.site >= kMaxSites)
        throw Error("tool sample of site " + std::to_string(s.site) + ": a stream holds sites 0.." +
                    std::to_string(kMaxSites - 1));
}

StrokeClose SiteSweeps::closes_before(const ToolSample& s, bool stroke_open) const {
    check(s);
    if (!stroke_open) return StrokeClose::kNo;
    const std::optional<ToolSample>& p = prev_[s.site];
    if (!p) return StrokeClose::kNo;
    if (s.site == open_site_) return sample_closes_stroke(*p, s) ? StrokeClose::kGestureEnds : StrokeClose::kNo;
    return cuts(s) ? StrokeClose::kSiteSwitch : StrokeClose::kNo;
}

std::size_t SiteSweeps::advance(const ToolSample& s, std::shared_ptr<const MeshTool> mesh,
                                const std::shared_ptr<const MeshTool>& mirrored_mesh, const Vec3& centre_m, double cell_m,
                                std::vector<Sweep>& out) {
    check(s);
    std::optional<ToolSample>& p = prev_[s.site];
    std::optional<ToolSample>& a = anchor_[s.site];
    // The site's gesture ends where its tool stops cutting or changes: its next stroke is a new one.
    if (!p || sample_closes_stroke(*p, s)) interrupted_by_[s.site].reset();
    p = s;
    // Only after a sweep of the stroke that is open: a sample left unswept always belongs to an open stroke, whose
    // close sweeps to it.
    if (swept_[s.site] && cuts(s) && within_sweep_spacing(*a, s, cell_m)) {
        unswept_[s.site] = true;
        return 0;
    }
    std::size_t n = 0;
    if (a && cuts(s)) n = sample_sweeps(*a, s, std::move(mesh), mirrored_mesh, centre_m, out);
    if (n > 0) open_site_ = s.site;
    a = s;
    unswept_[s.site] = false;
    swept_[s.site] = n > 0;
    return n;
}

std::size_t SiteSweeps::finish_strokes(const Vec3& centre_m, std::vector<Sweep>& out) {
    std::size_t n = 0;
    for (std::size_t k = 0; k < kMaxSites; ++k) {
        if (!unswept_[k]) continue;
        // within_sweep_spacing left only ball and flat-end tools unswept: no mesh is needed.
        n += sample_sweeps(*anchor_[k], *prev_[k], nullptr, nullptr, centre_m, out);
        anchor_[k] = prev_[k];
        unswept_[k] = false;
    }
    swept_.fill(false);  // the next sweep of any site opens a stroke
    return n;
}

void SiteSweeps::stroke_closed(std::optional<std::uint8_t> by_site) {
    if (by_site) interrupted_by_[open_site_] = *by_site;
    else interrupted_by_[open_site_].reset();
}

std::optional<std::uint8_t> SiteSweeps::interrupted_by(std::uint8_t site) const {
    return site < kMaxSites ? interrupted_by_[site] : std::nullopt;
}

const ToolSample* SiteSweeps::prev(std::uint8_t site) const {
    return site < kMaxSites && prev_[site] ? &*prev_[site] : nullptr;
}

void SiteSweeps::set_prev(const ToolSample& s) {
    check(s);
    prev_[s.site] = s;
    anchor_[s.site] = s;
    unswept_[s.site] = false;
    swept_[s.site] = false;
}

}  // namespace tridex::compute
