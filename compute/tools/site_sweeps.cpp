// compute/tools/site_sweeps.cpp - per-site sweeps and stroke closes of an interleaved sample stream.
#include "compute/tools/site_sweeps.hpp"

#include <string>

#include "compute/tools/sample_sweep.hpp"
#include "core/error.hpp"

namespace tridex::compute {

namespace {
bool cuts(const ToolSample& s) { return s.op != ToolOp::kNone && s.tool.radius_m > 0.0; }
}  // namespace

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
                                const std::shared_ptr<const MeshTool>& mirrored_mesh, const Vec3& centre_m,
                                std::vector<Sweep>& out) {
    check(s);
    std::optional<ToolSample>& p = prev_[s.site];
    // The site's gesture ends where its tool stops cutting or changes: its next stroke is a new one.
    if (!p || sample_closes_stroke(*p, s)) interrupted_by_[s.site].reset();
    std::size_t n = 0;
    if (p && cuts(s)) n = sample_sweeps(*p, s, std::move(mesh), mirrored_mesh, centre_m, out);
    if (n > 0) open_site_ = s.site;
    p = s;
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
}

}  // namespace tridex::compute
