// compute/tools/clay_kernel.hpp - the per-node and per-ray work of a clay operation behind one interface, so that
// the CPU reference and the GPU kernel (compute/gpu/gpu_clay.hpp) run the same operation from the same host steps.
#pragma once

#include <span>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "compute/tools/clay_field.hpp"

namespace tridex::compute {

/// One step of a grab (compute/tools/clay_grab.hpp): the grabbed point, the step's motion, the falloff's core and
/// radius of influence (grid units, cells).
struct ClayGrabParams {
    float anchor[3] = {0.0f, 0.0f, 0.0f};
    float v[3] = {0.0f, 0.0f, 0.0f};
    float core = 0.0f;
    float r = 0.0f;
};

/// One interaction point of a push or pull (Popescu, Burdea, Bouzit, section 3.3): the contact point p* (grid units
/// from the lattice origin), the outward surface normal there (unit, or 0), and the surface displacement at p*
/// (cells, > 0).
struct ClayStamp {
    float p[3] = {0.0f, 0.0f, 0.0f};
    float n[3] = {0.0f, 0.0f, 0.0f};
    float delta = 0.0f;
};

/// The constants of a push's or pull's displacement field (cells): the radius of influence r = kClayInfluence * R,
/// the rim width w = kClayRimWidth * r, reach2 = (r + w)^2 * 1.0001 (no stamp moves a node farther than that,
/// squared), sign = +1 (push: inward) or -1 (pull: outward) and the rim's cap (kClayMaxStep). Computed once on the host, in float, and used as they
/// are by every kernel, so every kernel sees the same bits.
struct ClayStampParams {
    float r = 0.0f;
    float w = 0.0f;
    float reach2 = 0.0f;
    float sign = 1.0f;
    /// The rim's weight at a node is min(delta, rim_cap) times its bump (cells): beta (at most kClayMaxBeta) scales
    /// it, so the rim rises at most kClayMaxBeta * rim_cap and only nodes that near the surface need an s1.
    float rim_cap = 1.0f;
};

/// The contact a smooth acts at: point and outward normal (grid units; ClayContact) and the radius of influence r
/// (cells).
struct ClaySmoothParams {
    float point[3] = {0.0f, 0.0f, 0.0f};
    float normal[3] = {0.0f, 0.0f, 0.0f};
    float r = 0.0f;
};

/// Where a clay operation's heavy steps run. The host steps around them (stamps and contacts, the field's box and
/// region, the beta solve, writing the rays, dirty tiles, `before` images) are the same for every kernel
/// (clay_push, clay_pull, clay_smooth, apply_clay), so two kernels that fill the same field and re-sample the same
/// rays bit for bit give the same model and the same ClayStats. Not thread-safe unless an implementation says so.
class ClayKernel {
public:
    virtual ~ClayKernel() = default;
    /// Fills `field` (box and region set by the caller, search as wanted) for a push or pull: phi, s0, s1 and chords
    /// exactly as clay_build_phi followed by clay_stamp_offsets. Throws tridex::Error on a device failure.
    virtual void stamp_field(const TriDexel& model, ClayField& field, std::span<const ClayStamp> stamps,
                             const ClayStampParams& params) = 0;
    /// Fills `field` for a smooth of one or more acts (in order): exactly clay_build_phi followed by
    /// clay_smooth_offsets. Throws as stamp_field.
    virtual void smooth_field(const TriDexel& model, ClayField& field, std::span<const ClaySmoothParams> acts) = 0;
    /// Fills `field` for one step of a grab: exactly clay_build_phi followed by clay_grab_offsets. Throws as
    /// stamp_field.
    virtual void grab_field(const TriDexel& model, ClayField& field, const ClayGrabParams& params) = 0;
    /// Re-samples `field` into `model` exactly as clay_resample (volume-preserving) and writes the changed rays where
    /// this kernel keeps its model too. Throws tridex::Error on a device failure.
    virtual ClayStats resample(TriDexel& model, const ClayField& field, std::vector<RayImage>* before) = 0;
};

/// The CPU reference kernel (one thread; clay_build_phi, clay_stamp_offsets, clay_smooth_offsets, clay_resample).
/// Stateless, so one shared instance serves every thread.
ClayKernel& clay_cpu_kernel();

/// The CPU reference of a push's or pull's s0 and s1 (clay_push.hpp describes the field): at every node of the
/// field's region that clay_node_fixed lets move, in z, y, x order, over the stamps in order. field.phi must be built.
void clay_stamp_offsets(const TriDexel& model, ClayField& field, std::span<const ClayStamp> stamps,
                        const ClayStampParams& params);

/// The CPU reference of a grab step's s0 and s1: at every node x of the field's region that clay_node_fixed lets
/// move, in z, y, x order, with d = |x - anchor| < r, w = clay_grab_falloff(d) (clay_grab.hpp), u = w * v and
/// s0(x) = phi(x - u) - phi(x) (phi trilinear in the field's nodes, clay_phi_at), so that phi + s0 is phi advected by
/// u: phi'(x) = phi(x - u(x)); s1(x) = w where |phi + s0| < kClayMaxBeta + 1 (the volume correction follows the
/// motion). Every node within r + |v| + 2 cells of the anchor must be in field.region and the box. field.phi must be
/// built.
void clay_grab_offsets(const TriDexel& model, ClayField& field, const ClayGrabParams& params);

/// The CPU reference of a smooth's s0 and s1 for its acts in order (clay_smooth.hpp describes the field): act k takes
/// one Laplacian step of psi = phi + s0 as the acts before it left s0 (every node's step from the same psi, then
/// added to s0: s0 = s0 + step), and s1 = max(s1, w_k). One act gives s0 = its step of phi, s1 = its falloff.
/// field.phi must be built, with every neighbour of a node an act may move inside field.region.
void clay_smooth_offsets(const TriDexel& model, ClayField& field, std::span<const ClaySmoothParams> acts);

}  // namespace tridex::compute
