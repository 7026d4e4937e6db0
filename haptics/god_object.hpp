// haptics/god_object.hpp - god-object (IHIP) contact on the active triangle of three dexel points.
#pragma once

#include "core/active_surface.hpp"
#include "core/math.hpp"

namespace tridex::haptics {

/// Contact model parameters (SI units; defaults are the Omni-class values of DESIGN.md).
struct ContactParams {
    double stiffness_n_per_m = 700.0;  ///< kp, N/m (0.7 N/mm: stable on Omni-class devices at 1 kHz), >= 0
    double damping_n_s_per_m = 0.5;    ///< kd on the penetration rate, N*s/m, >= 0
    double tool_radius_m = 0.0;        ///< radius r of the ball tool centred on the HIP, m; 0 = point tool
};

/// The outcome of one god-object update (world frame).
struct ContactResult {
    Vec3 proxy_m{0.0};    ///< god-object position, m: on the surface (offset by r) in contact, = HIP otherwise
    Vec3 force_n{0.0};    ///< force on the user, N: kp*depth*n + kd*(d depth/dt)*n, never pulling; zero when free
    Vec3 normal{0.0};     ///< outward unit normal of the active triangle in contact, zero otherwise
    double depth_m = 0.0; ///< penetration depth r - (hip - q0).n, m (> 0 in contact, 0 otherwise)
    bool contact = false; ///< true when depth > 0 on a complete active triangle
    int axis = -1;        ///< ray set (0 = X, 1 = Y, 2 = Z) of the active triangle in contact, -1 when free
};

/// God-object (intermediate haptic interaction point, IHIP) on tri-dexel data.
/// Source: Peng et al., "Haptic Interface Technique in Large-Scale Virtual Environment": the surface
/// near the HIP is the "active triangle" of three dexel points, F = kp*dx + kd*v.
///
/// Each update:
/// 1. Candidate ray sets, in order: the axis best aligned with the approach direction (the previous
///    contact normal while in contact, else HIP - proxy, i.e. the HIP's motion since the last tick; when
///    that is zero, the axis used last, initially Z), then the other two in order of alignment. The
///    first candidate that gives a contact (steps 2-4) wins.
/// 2. Active triangle: the lattice cell of that set's window (ActiveSurface) around the HIP's
///    projection is split along its (0,0)-(1,1) diagonal; the three rays of the half holding the
///    HIP are used. On each ray the interval end nearest the reference point is taken (the proxy's
///    contact point proxy - r*n while in contact, else the proxy): these are the three dexel points
///    q0, q1, q2. Keeping to the proxy's side stops the god-object from popping through thin material.
/// 3. Normal: n = unit (q1 - q0) x (q2 - q0), oriented outward by the ends' type (a majority of exit
///    ends -> n along +axis, of enter ends -> -axis).
/// 4. Contact when depth = r - (hip - q0).n > 0 and the god-object was not already behind that plane
///    (r - (proxy - q0).n <= cell/4): the constraint-plane rule of the god-object (Zilles & Salisbury
///    1995), an extension of the brief's single-axis rule. It keeps faces the proxy is already behind
///    (the far end of a ray, a wall the proxy slid under) from grabbing the tool, and lets the other
///    ray sets catch an oblique approach whose best-aligned rays straddle the surface.
///    Then the proxy is hip + depth*n (the ball resting on the surface) and
///    force = max(0, kp*depth + kd*(depth - depth_prev)/dt) * n, depth_prev = 0 on the first tick of a
///    contact. Otherwise (or when the snapshot is empty, the HIP's projection lies outside every
///    window, or a ray of the triangle is empty) proxy = hip and the force is zero.
/// With r = 0 this is the point god-object. Behaviour to know:
/// - A HIP that goes through a slab thinner than its penetration (even in one tick) stays in contact
///   with the side it entered: the proxy stays on that side and the force keeps growing as kp*depth
///   (the loop clamps it) until the HIP comes back out that side.
/// - A HIP that starts inside material (first update, or material added over it) feels nothing until it
///   leaves: there is no plane it crossed.
/// - One active triangle at a time: a concave corner is rendered by one face (no multi-plane proxy).
/// - The ball is sampled only along the rays around its centre: a ball touching material its centre's
///   rays miss feels nothing.
/// update() is allocation-free, lock-free and takes a few microseconds, whatever the model size.
class GodObject {
public:
    /// Throws tridex::Error naming the field when a parameter is negative or not finite.
    explicit GodObject(ContactParams params);

    /// One contact update for the HIP at hip_m (world m) against the snapshot `surface`; dt_s (s) is the
    /// time since the previous update (the damping term is dropped when dt_s is not > 0). A non-finite
    /// HIP gives no contact, zero force, and resets the god-object.
    ContactResult update(const ActiveSurface& surface, const Vec3& hip_m, double dt_s);
    /// Forgets the proxy and contact history (the next update starts free, with the proxy on the HIP).
    void reset();
    /// The parameters.
    const ContactParams& params() const { return params_; }

private:
    // Active triangle on ray set `axis`: its first point q0 (m) and outward unit normal n.
    // False when the window is empty, the HIP is outside it, or a ray of the triangle is empty.
    bool active_triangle(const ActiveSurface& s, int axis, const Vec3& hip, const Vec3& reference, Vec3& q0,
                         Vec3& n) const;

    ContactParams params_;
    bool has_proxy_ = false;
    bool in_contact_ = false;
    Vec3 proxy_{0.0};
    Vec3 normal_{0.0};
    double depth_ = 0.0;
    int last_axis_ = 2;
};

}  // namespace tridex::haptics
