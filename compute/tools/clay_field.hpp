// compute/tools/clay_field.hpp - the implicit field behind the clay tools (push, smooth, pull, grab): one signed
// distance on the lattice nodes of a box, built from all three ray sets, offset, and re-sampled into all three sets.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/boolean.hpp"

namespace tridex::compute {

/// How the clay tools keep the three ray sets describing one solid.
///
/// A clay operation never moves interval ends of one set on its own. It (1) builds one scalar field phi on the
/// lattice nodes of the operation's region (a capsule inside its box around the nodes it can move: a narrow region, not
/// the whole box) from all three sets (clay_build_phi: the sign is the majority of the three
/// rays through the node, the magnitude the plane-exact distance 1 / sqrt(sum_a 1/d_a^2) from the axial distances
/// d_a to the nearest crossing on each of the three rays), (2) offsets it by a displacement s >= or <= 0 per node
/// (phi' = phi + s moves the surface along its normal by s cells: inward for s > 0), and (3) re-samples every ray
/// of every set in the box from phi' (clay_resample): on a lattice edge whose two end nodes both kept phi' == phi
/// the ray's old crossings are copied bit for bit, on every other edge the ray crosses where phi' changes sign
/// (linear root), so all three sets take their node occupancy from the same field and their crossings from the same
/// linear interpolant. The three sets can then only disagree where they already did (a node on whose status the
/// old rays disagreed) and by the sub-cell rounding of the roots; clay_set_disagreement measures it in cells.
/// All arithmetic on the field is in float (the sums of interval lengths in double), in a fixed order, so a GPU
/// port compiled without fused multiply-add can repeat it bit for bit.

/// Radius of influence r as a multiple of the tool radius R (Popescu, Burdea, Bouzit, section 3.3).
inline constexpr float kClayInfluence = 1.5f;
/// Width of the push's rim beyond the radius of influence, as a multiple of r.
inline constexpr float kClayRimWidth = 0.5f;
/// How far (cells) the field looks along each ray for the nearest crossing; farther is clamped to this. Kept short so
/// that the distance near a surface is not bent by another sheet farther away (a plane stays exactly linear); the
/// contact of a large tool looks farther (ClayField::search).
inline constexpr int kClaySearchCells = 6;
/// Largest |beta| the volume solve may pick (clay_resample): the rim or moat of a push or pull rises at most this
/// many times its stamp's displacement, so only nodes within kClayMaxBeta * |s1| + 2 cells of the surface need an s1.
inline constexpr float kClayMaxBeta = 3.0f;
/// Node layers around the displaced nodes that keep phi' == phi, so a ray's re-sampled part joins its old part.
inline constexpr int kClayMarginCells = 2;

/// A box of lattice nodes [lo, hi] (inclusive), clamped to the lattice.
struct ClayBox {
    int lo[3] = {0, 0, 0};
    int hi[3] = {-1, -1, -1};
    bool empty() const { return hi[0] < lo[0] || hi[1] < lo[1] || hi[2] < lo[2]; }
    int n(int a) const { return hi[a] - lo[a] + 1; }
    std::size_t count() const { return empty() ? 0 : static_cast<std::size_t>(n(0)) * n(1) * n(2); }
    std::size_t index(int i, int j, int k) const {
        return static_cast<std::size_t>(i - lo[0]) +
               static_cast<std::size_t>(n(0)) *
                   (static_cast<std::size_t>(j - lo[1]) + static_cast<std::size_t>(n(1)) * (k - lo[2]));
    }
    /// Index step between neighbouring nodes along axis a (ClayBox::index order).
    std::size_t stride(int a) const {
        return a == 0 ? 1 : a == 1 ? static_cast<std::size_t>(n(0)) : static_cast<std::size_t>(n(0)) * n(1);
    }
    /// True when node (i, j, k) (lattice node indices) lies in the box.
    bool contains(int i, int j, int k) const {
        return i >= lo[0] && i <= hi[0] && j >= lo[1] && j <= hi[1] && k >= lo[2] && k <= hi[2];
    }
};

/// The capsule of grid space (the points within r cells of the segment c..c1, grid units from the lattice origin;
/// c1 == c: a ball) outside which a field's operation reads no node: its nodes are the narrow region clay_build_phi
/// fills. r = infinity: the whole box.
struct ClayRegion {
    float c[3] = {0.0f, 0.0f, 0.0f};
    float c1[3] = {0.0f, 0.0f, 0.0f};
    float r = std::numeric_limits<float>::infinity();
    /// A ball of radius r around c.
    void ball(const float centre[3], float radius) {
        for (int a = 0; a < 3; ++a) c[a] = c1[a] = centre[a];
        r = radius;
    }
    /// Squared distance (cells^2) from grid point (x, y, z) to the segment c..c1: to its nearest point at parameter
    /// clamp(((q - c) . e) / (e . e), 0, 1), e = c1 - c (0 when e = 0), in float, in that order.
    float distance2(float x, float y, float z) const {
        const float q[3] = {x - c[0], y - c[1], z - c[2]};
        const float e[3] = {c1[0] - c[0], c1[1] - c[1], c1[2] - c[2]};
        const float ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        float t = 0.0f;
        if (ee > 0.0f) t = std::clamp((q[0] * e[0] + q[1] * e[1] + q[2] * e[2]) / ee, 0.0f, 1.0f);
        const float dx = q[0] - t * e[0], dy = q[1] - t * e[1], dz = q[2] - t * e[2];
        return dx * dx + dy * dy + dz * dz;
    }
    /// True when lattice node (i, j, k) lies in the capsule: distance2 <= r^2 (the same predicate wherever a node's
    /// membership is asked).
    bool contains(int i, int j, int k) const {
        return distance2(static_cast<float>(i), static_cast<float>(j), static_cast<float>(k)) <= r * r;
    }
};

/// The signed distance phi (cells; < 0 inside) at every node of `box` within `region` (NaN at the box's other nodes,
/// which the operation must not read), and the displacement s = s0 + beta * s1 (cells along the surface normal,
/// > 0 inward) the operation applies there. s0, s1 are 0 where nothing moves (and everywhere outside `region`).
struct ClayField {
    ClayBox box;
    ClayRegion region;
    float search = static_cast<float>(kClaySearchCells);  ///< clamp of phi, cells (clay_node_phi)
    std::vector<float> phi;
    std::vector<float> s0;
    std::vector<float> s1;
    /// The volume change (cells^3) a volume-preserving re-sampling aims at instead of 0: a grab's own (the
    /// divergence of its motion over the material, clay_grab.hpp); 0 for push, pull and smooth.
    double volume_target = 0.0;
    /// Filled by clay_build_phi: per set a, per ray of the box through (u, v) (its other two node indices), the run
    /// [lo, hi] of its depth nodes in the region (clay_region_chord; lo > hi when none).
    std::array<std::vector<std::array<int, 2>>, 3> chords;
    /// The run of region nodes on the ray of set a through box nodes (u, v), from `chords`.
    const std::array<int, 2>& chord(int a, int u, int v) const {
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        return chords[a][static_cast<std::size_t>(u - box.lo[ua]) +
                         static_cast<std::size_t>(box.n(ua)) * static_cast<std::size_t>(v - box.lo[va])];
    }
};

/// True when node (i, j, k) of set `axis`'s ray through it lies inside material: some interval has
/// enter < depth <= exit (the parity of the ray's crossings below the node).
bool clay_ray_inside(const std::vector<Interval>& ray, float depth);

/// phi at one lattice node (cells, < 0 inside; |phi| <= search; never exactly 0), from the three rays through it
/// (see above), crossings farther than `search` cells along a ray ignored. O(intervals on the three rays).
float clay_node_phi(const TriDexel& model, int i, int j, int k, float search = static_cast<float>(kClaySearchCells));

/// Fills field.phi at the nodes of field.box (which must be inside the lattice) within field.region, NaN at the
/// others, zeroes s0 and s1, and fills field.chords. Each ray of the three sets through the box is walked only over
/// its chord through the region, so the cost is O(nodes in the region + intervals on those rays), plus clearing the
/// box's arrays.
void clay_build_phi(const TriDexel& model, ClayField& field);

/// Fills field.chords (see ClayField::chords) from field.box and field.region alone (clay_region_chord per ray of
/// each set through the box; rows that miss the region are skipped). clay_build_phi calls it; a GPU field build
/// (compute/gpu/gpu_clay.hpp) calls it to know the region's nodes. O(rays of the three sets through the box).
void clay_build_chords(ClayField& field);

/// The depth nodes [lo, hi] of the ray of set `axis` through (u, v) (its other two node indices) that lie both in
/// field.box and in field.region (ClayRegion::contains, exactly); lo > hi when there are none. O(1).
void clay_region_chord(const ClayField& field, int axis, int u, int v, int& lo, int& hi);

/// Trilinear phi at grid point p (cells from the lattice origin) from the nodes of field.box; p is clamped into the box.
float clay_phi_at(const ClayField& field, float px, float py, float pz);

/// What clay_resample did.
struct ClayStats {
    BooleanStats rays;                    ///< rays of the three sets in the box, and those whose intervals changed
    double volume_change_cells = 0.0;     ///< volume after - before in the box, cells^3 (mean of the three sets)
    double beta = 0.0;                    ///< the s1 weight used (volume_preserving: solved so the volume is kept)
    double max_displacement_cells = 0.0;  ///< largest |s| at a node, cells
};

/// Re-samples every ray of the three sets through field.box from phi + s0 + beta * s1 (see above) and writes the
/// rays that changed. With `volume_preserving`, beta is solved so that the model's own volume in the box (the mean of
/// the three sets' interval lengths, ray_set_volume_m3 without the face correction of dexel_volume_m3) changes by
/// field.volume_target (0: is kept): on
/// the edge-by-edge prediction of the change the re-sampling will measure (ClayVolumeModel,
/// clay_volume_model.hpp), then, in the rare case the measured change still exceeds 1% of what s0 moved (or a
/// hundredth of a cell^3), up to two more re-samplings with the prediction shifted by its error. Else beta = 0. Only
/// nodes of field.region (field.chords as clay_build_phi fills them; the whole box when they are missing) are read
/// (s0 and s1 must be 0 elsewhere), and phi only at the moved nodes and their neighbours along the rays. Appends the
/// changed rays' old images to `before` when not null. Marks dirty the cells around the interval ends that changed (changed_span). Cost: O(nodes in the region) to
/// find the moved nodes, O(moved rays x (moved span + intervals)) to build the prediction and per re-sampling, a few
/// sums over the edges near the surface to solve it; usually one re-sampling (the best one is written).
ClayStats clay_resample(TriDexel& model, const ClayField& field, bool volume_preserving,
                        std::vector<RayImage>* before = nullptr);

/// Three-set disagreement of `model` within node box `box`: the number of lattice nodes on whose inside/outside
/// status the three rays through it do not all agree (each such node is one cell of disagreement).
std::size_t clay_set_disagreement(const TriDexel& model, const ClayBox& box);

/// How far (cells) the surface of `after` lies from the surface of `before` (two models on one lattice), the
/// largest over every interval end of the rays that differ, both ways: |phi| of the other model at the end, phi
/// trilinear in the 8 nodes around it (clay_node_phi looking 64 cells along the rays), so at most 64. 0 when no ray differs. The
/// `deformation.max_displacement_m` of a clay session's report (times the cell size). O(changed rays x intervals).
double clay_max_displacement_cells(const TriDexel& before, const TriDexel& after);

/// The node box around grid points lo..hi (per axis) widened by `reach` cells and kClayMarginCells, inside `outer`.
ClayBox clay_support_box(const float lo[3], const float hi[3], float reach, const ClayBox& outer);

/// The node box of the whole lattice.
ClayBox clay_whole_box(const Lattice& lattice);

/// True when node (ix, jy, kz) (lattice node indices) of `box` must keep its field value: it lies in the box's outer
/// kClayMarginCells layers or on the lattice's own boundary. Push and smooth move only the other nodes.
inline bool clay_node_fixed(const ClayBox& box, const Lattice& lattice, int ix, int jy, int kz) {
    const int nd[3] = {ix, jy, kz};
    for (int a = 0; a < 3; ++a)
        if (nd[a] - box.lo[a] < kClayMarginCells || box.hi[a] - nd[a] < kClayMarginCells || nd[a] == 0 ||
            nd[a] == lattice.cells[a])
            return true;
    return false;
}

/// The nodes along axis a that clay_node_fixed lets move (ignoring the other two axes): [lo, hi], lo > hi when none.
/// A node moves exactly when each of its three indices lies in its axis' range.
inline void clay_movable_range(const ClayBox& box, const Lattice& lattice, int a, int& lo, int& hi) {
    lo = std::max(box.lo[a] + kClayMarginCells, 1);
    hi = std::min(box.hi[a] - kClayMarginCells, lattice.cells[a] - 1);
}

/// Calls fn(ix, jy, kz, i) for every node of `field`'s region that clay_node_fixed lets move, in z, y, x order
/// (grid indices; i = field.box.index(ix, jy, kz)), walking each x-row only over its region chord. The field's
/// phi must be built (clay_build_phi). Never throws unless fn does.
template <class Fn>
void clay_for_each_movable_node(const TriDexel& model, const ClayField& field, Fn&& fn) {
    const ClayBox& b = field.box;
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) clay_movable_range(b, model.lattice, a, lo[a], hi[a]);
    for (int kz = lo[2]; kz <= hi[2]; ++kz)
        for (int jy = lo[1]; jy <= hi[1]; ++jy) {
            const std::array<int, 2>& run = field.chord(0, jy, kz);
            for (int ix = std::max(run[0], lo[0]); ix <= std::min(run[1], hi[0]); ++ix)
                fn(ix, jy, kz, b.index(ix, jy, kz));
        }
}

}  // namespace tridex::compute
