// compute/tools/clay_volume_model.hpp - the volume change a clay field's re-sampling will measure, as a function of
// the rim weight beta, predicted edge by edge without re-sampling, and the beta that keeps the volume.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/clay_field.hpp"
#include "compute/tools/clay_resample.hpp"

namespace tridex::compute {

/// Width of beta's bracket (a multiple of s1, cells per cell of s1) at which ClayVolumeModel::solve stops: the
/// rim it decides moves by at most this much of a cell per cell of rim, and a jump of the change there (a node whose
/// status flips) cannot be split finer anyway.
inline constexpr float kClayBetaResolution = 1e-3f;

/// Span of beta (cells of s1) over which the Newton slope of ClayVolumeModel::solve lets one edge's length change by
/// a whole cell at most.
inline constexpr double kClaySlopeSpan = 0.25;

/// The model's volume change (cells^3, the mean of the three sets' interval lengths, as clay_resample measures it)
/// that re-sampling field `f` at beta gives, predicted per lattice edge.
///
/// clay_resample_ray rebuilds a moved ray edge by edge, and what it puts on an edge [d, d + 1] depends only on the
/// edge's two end nodes: an edge whose ends both keep their value keeps its old crossings; on any other edge each end
/// is inside or outside (the field's sign phi + s0 + beta * s1 at a moved end, the ray's own parity at a still one),
/// and the edge is wholly inside, wholly outside, or split at the field's linear root (at its middle when the field
/// does not change sign there). So the length a ray gains on the edge is a function of beta alone, and the volume
/// change is the sum of those over the moved rays' edges, divided by 3. Edges whose ends carry no s1 add a constant;
/// so do edges whose two ends stay on one side of the surface for every beta in range; only the others are kept and
/// summed per beta. The prediction equals the re-sampling's own measure up to
/// the float rounding of the crossings (the interval lengths are summed in a different order), so a beta solved on
/// it needs no trial re-samplings. Not thread-safe; reusable (build replaces everything).
class ClayVolumeModel {
public:
    /// Reads the field and the old rays of the moved rays `moved` (clay_moved_rays of `f`). O(moved rays x (span +
    /// intervals)).
    void build(const TriDexel& model, const ClayField& f, std::span<const ClayMovedRay> moved);
    /// The predicted volume change at beta, cells^3, and when `slope` is not null its derivative in beta over the
    /// crossings that slide along their edges (the jumps where a node's status flips left out; each edge's rate
    /// capped at 1 / kClaySlopeSpan), cells^3 per unit beta. O(edges that depend on beta).
    double change(float beta, double* slope = nullptr) const;
    /// beta in [-kClayMaxBeta, kClayMaxBeta] where change(beta) = target (cells^3): a Newton step from 0 with the
    /// slope of change (each edge's rate capped, kClaySlopeSpan), then outward along the secant (at least doubling)
    /// until the change brackets the target or the range ends, then regula falsi with the Anderson-Bjorck rule on
    /// the bracket, bisecting when two steps did not halve it (the change is monotone in beta up to the jumps where a
    /// node's status flips),
    /// until a bracket end lies within `tolerance` (cells^3) of the target, the bracket is narrower than
    /// kClayBetaResolution, or 40 steps, returning the end nearer to the target (the range's end nearer to it when the
    /// target lies outside the range's values).
    float solve(double target, double tolerance) const;
    /// Number of edges whose length depends on beta (for tests and statistics).
    std::size_t varying_edges() const { return edges_.size(); }

private:
    static constexpr std::uint8_t kMoved0 = 1, kMoved1 = 2, kInside0 = 4, kInside1 = 8;
    /// An edge whose length depends on beta: the field at its ends is a + beta * b (a = phi + s0, b = s1; the
    /// re-sampling adds in another order, so this is its value up to rounding), and where an end keeps its value
    /// (not kMoved) the old ray's status there (kInside) decides.
    struct Edge {
        float a0, b0;
        float a1, b1;
        float old_inside;  ///< the old ray's inside length on the edge, cells
        std::uint8_t flags;
    };
    std::vector<Edge> edges_;
    double constant_ = 0.0;  ///< sum over the edges without an s1 end of (new - old) inside length, cells
};

}  // namespace tridex::compute
