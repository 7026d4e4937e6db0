// compute/tools/clay_resample.hpp - re-sampling the rays of a clay field's box from phi + s0 + beta * s1, with the
// volume-keeping solve for beta shared by the CPU reference and the GPU kernel (compute/gpu/gpu_clay.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/clay_field.hpp"

namespace tridex::compute {

/// A node of a clay field with s0 or s1 != 0: its index in the field's box and its lattice node indices.
struct ClayMovedNode {
    std::uint32_t x = 0;
    int n[3] = {0, 0, 0};
};

/// A ray of the box that holds a moved node: its set, its index in the set, its (u, v), the depth nodes [lo, hi] its
/// re-sampling walks (the moved nodes' span widened by one node each way, inside the box), whether a node on it has
/// s1 != 0 (else its re-sampling is the same for every beta), and its old length (cells, the sum in double of its
/// intervals' exit - enter).
struct ClayMovedRay {
    std::uint8_t set = 0;
    std::uint32_t index = 0;
    int u = 0, v = 0, lo = 0, hi = -1;
    bool varies = false;
    double old_length = 0.0;
};

/// One re-sampling of some of the moved rays, slot k for moved ray k: whether it changed (0/1), its new intervals
/// and its length change (cells; 0 when unchanged). Slots of rays not re-sampled are left as they were.
struct ClayResampled {
    std::vector<std::uint8_t> changed;
    std::vector<std::vector<Interval>> rays;
    std::vector<double> dlen;
};

/// A ray of a model by set and index in the set (RayImage without the intervals).
struct ClayRayRef {
    std::uint8_t set = 0;
    std::uint32_t index = 0;
};

/// Re-samples the moved rays of a field: those with varies == true at `beta` into `var`, and when `fixed` is not null
/// those with varies == false (at beta 0; their result does not depend on beta) into `fixed`. Each re-sampled slot k
/// must hold what clay_resample_ray gives for moved[k] bit for bit, with changed and dlen as clay_note_resampled sets
/// them. The slots are sized (moved.size()) before the call. May throw tridex::Error (a device failure).
using ClayResampleFn =
    std::function<void(std::span<const ClayMovedRay> moved, float beta, ClayResampled* fixed, ClayResampled& var)>;

/// True when the two rays hold the same intervals, bit for bit (depths and materials).
bool clay_same_ray(const std::vector<Interval>& a, const std::vector<Interval>& b);

/// Sum over the ray's intervals of exit - enter in double, in order (cells).
double clay_ray_length(const std::vector<Interval>& ray);

/// The CPU reference for one ray: ray `ray` (set `axis`, node (u, v)) re-sampled from field `f` at `beta` over its
/// edges between depth nodes [lo, hi] that touch a moved node (clay_field.hpp describes the rule); the rest of the
/// ray is kept. `out` (replaced) gets the new intervals: sorted, disjoint, non-touching. O(intervals + hi - lo).
void clay_resample_ray(const std::vector<Interval>& ray, const ClayField& f, int axis, int u, int v, int lo, int hi,
                       float beta, std::vector<Interval>& out);

/// Sets out.changed[k] and out.dlen[k] for moved ray `m` whose new intervals are out.rays[k] and old ones `old`.
void clay_note_resampled(const std::vector<Interval>& old, const ClayMovedRay& m, std::size_t k, ClayResampled& out);

/// The moved nodes of the field's region (s0 or s1 != 0) in increasing box index, walking the chords of set 0
/// (field.chords) or, when they are not built, the whole box.
void clay_moved_nodes(const ClayField& f, std::vector<ClayMovedNode>& out);

/// The moved rays of the three sets (those through a moved node), in the order set, v, u.
void clay_moved_rays(const TriDexel& model, const ClayField& f, std::span<const ClayMovedNode> nodes,
                     std::vector<ClayMovedRay>& out);

/// The CPU re-sampler (a ClayResampleFn over `model` and `f`): clay_resample_ray per ray.
void clay_resample_on_cpu(const TriDexel& model, const ClayField& f, std::span<const ClayMovedRay> moved, float beta,
                          ClayResampled* fixed, ClayResampled& var);

/// clay_resample (clay_field.hpp) with the re-sampling done by `resample`: finds the moved nodes and rays on the
/// host, solves beta (on ClayVolumeModel's prediction, then, when the measured change is still over tolerance, up to
/// two more calls of `resample` with the prediction shifted by its error), writes the changed rays into `model` in
/// the order set, v, u, appends their old images to `before` and their references to `written` (each when not
/// null), marks dirty the cells around the interval ends that changed (changed_span), and returns the stats. One to three calls of `resample` (almost always one), the
/// first with `fixed` set. Throws what `resample` throws (the model is then
/// unchanged).
ClayStats clay_resample_with(TriDexel& model, const ClayField& f, bool volume_preserving,
                             std::vector<RayImage>* before, const ClayResampleFn& resample,
                             std::vector<ClayRayRef>* written = nullptr);

}  // namespace tridex::compute
