// haptics/god_object.hpp - god-object (IHIP) contact on the active triangle of three dexel points,
// with per-material stiffness, damping and Coulomb friction, force shading and a cutting reaction.
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "core/active_surface.hpp"
#include "core/math.hpp"
#include "haptics/constraint_plane.hpp"
#include "haptics/materials.hpp"

namespace tridex::haptics {

/// Contact model parameters (SI units; defaults are the Omni-class values of DESIGN.md, no friction,
/// force shading on, cutting off).
struct ContactParams {
    double stiffness_n_per_m = 700.0;  ///< kp, N/m (0.7 N/mm: stable on Omni-class devices at 1 kHz), >= 0
    double damping_n_s_per_m = 0.5;    ///< kd on the penetration rate, N*s/m, >= 0
    double tool_radius_m = 0.0;        ///< radius r of the ball tool centred on the HIP, m; 0 = point tool
    double static_friction = 0.0;      ///< Coulomb mu_s (>= 0) of the material used when `materials` is null
    double dynamic_friction = 0.0;     ///< Coulomb mu_d (0 <= mu_d <= mu_s) of that material
    /// Materials by ActiveSurface interval material id; null = every id uses the material
    /// {stiffness_n_per_m, damping_n_s_per_m, static_friction, dynamic_friction} above.
    std::shared_ptr<const MaterialTable> materials = nullptr;
    bool force_shading = true;  ///< force direction from blended vertex normals (Popescu et al. 3.2)
    bool cutting = false;       ///< add the cutting reaction (cutting_force.hpp) while in contact
    double cutting_coefficient_n_per_m2 = 2e5;  ///< specific cutting force k_c, N/m^2 (wax-like), >= 0
    double cutting_fade_speed_m_per_s = 0.01;   ///< speed at which the cutting force reaches full size, m/s, > 0
};

/// The outcome of one god-object update (world frame).
struct ContactResult {
    Vec3 proxy_m{0.0};    ///< god-object position (ball centre), m: outside material in contact, = HIP otherwise
    Vec3 force_n{0.0};    ///< force on the user, N: spring + damping along `normal` (never pulling), friction, cutting
    Vec3 normal{0.0};     ///< outward unit contact normal (shaded when force_shading), zero when free
    double depth_m = 0.0; ///< penetration depth along the active triangle's normal, m (> 0 in contact, 0 otherwise)
    bool contact = false; ///< true when the god-object holds the HIP back (depth > 0, or held by the guard)
    int axis = -1;        ///< ray set (0 = X, 1 = Y, 2 = Z) of the active triangle in contact, -1 when none
    Vec3 plane_normal{0.0};           ///< outward unit normal of the active triangle's plane, zero when none
    std::array<Vec3, 3> triangle_m{}; ///< the active triangle's three dexel points, m (zeros when none)
    int material = -1;                ///< material id of the interval touched (-1 when free)
    bool sliding = false;             ///< friction: the proxy slid this tick (tangential force at mu_d*|F_n|)
    bool held = false;                ///< the proxy's move was stopped where it would have entered material
    bool hip_inside = false;          ///< a reading of the snapshot (read_depth) puts the HIP inside material
    Vec3 cutting_force_n{0.0};        ///< cutting reaction (part of force_n), N
    /// Where the tool meets the surface, m: the ball's point proxy - r*n along the constraint normal n
    /// in contact (the proxy for a point tool, or when held with no plane known); the HIP when free.
    Vec3 contact_point_m{0.0};
};

/// God-object (intermediate haptic interaction point, IHIP) on tri-dexel data.
/// Source: Peng et al., "Haptic Interface Technique in Large-Scale Virtual Environment": the surface
/// near the HIP is the "active triangle" of three dexel points, F = kp*dx + kd*v; the constraint-plane
/// rule of Zilles & Salisbury (1995).
///
/// Each update:
/// 1. Candidate ray sets, in order: the axis best aligned with the approach direction (the previous
///    contact normal while in contact, else HIP - proxy, i.e. the HIP's motion since the last tick; when
///    that is zero, the axis used last, initially Z), then the other two in order of alignment. The
///    first candidate that gives a contact (steps 2-4) wins.
/// 2. Active triangle: the lattice cell of that set's window (ActiveSurface) around the HIP's
///    projection is split along its (0,0)-(1,1) diagonal; the three rays of the half holding the
///    HIP are used. On each ray the interval end nearest the reference point is taken (last tick's
///    contact point while in contact, else the proxy): these are the dexel points q0, q1, q2. Keeping
///    to the proxy's side stops the god-object from popping through thin material. The triangle is
///    formed anew each tick, so a new one is used as soon as the HIP leaves the current one's cover
///    (its half cell). Locality: an end farther than 3 cells + 2 x the HIP-reference lateral distance
///    (+ the tick's motion and r while free) from the reference rejects the triangle: its rays straddle
///    a feature (one passes under a slot's floor) and its plane is no face.
/// 3. Normal: n = unit (q1 - q0) x (q2 - q0), oriented outward by the ends' type (a majority of exit
///    ends -> n along +axis, of enter ends -> -axis).
/// 4. Contact when depth = r - (hip - q0).n > 0 and the god-object was not already behind that plane
///    (r - (proxy - q0).n <= cell/4). It keeps faces the proxy is already behind (the far end of a
///    ray, a wall the proxy slid under) from grabbing the tool, and lets the other ray sets catch an
///    oblique approach. If no set gives a contact while in contact and the HIP is inside material, the
///    search is repeated with the triangles under last tick's contact point (a HIP deep under a curved
///    surface has no face of the proxy's side above it). A ball with no plane under its centre, or with a
///    triangle spanning an edge (no local surface fits it) or a plane that leaves material the ball touches
///    unexplained, meets a convex edge or corner: its faces are gathered around the ball, the point x* of
///    their intersection nearest the HIP is found exactly, and the plane is the tangent plane of the solid
///    grown by r there (normal hip - x*, depth r - |hip - x*|; convex_contact.hpp); no force shading on it.
///    Failing all that the last plane is kept (a face's band between its last complete triangle and its
///    edge, up to a cell, has no triangle).
/// 5. Material: the id of the interval whose end is the triangle vertex with the largest barycentric
///    weight of the HIP's projection selects kp, kd, mu_s, mu_d (ContactParams.materials).
/// 6. Friction (friction.hpp): last tick's proxy projected on the plane sticks while the tangential
///    spring force stays inside the cone |F_t| <= mu_s*|F_n| (mu_d once sliding); beyond it the proxy
///    slides so that |F_t| = mu_d*|F_n|. Without friction the proxy is hip + depth*n.
/// 7. Guard, so the proxy never ends inside material: the move from last tick's proxy to the proposed
///    one (the HIP itself when there is no plane) is sampled every half cell for the centre and, for a
///    ball, its contact point and its six points at +-r along the axes; where one of them would be more
///    than a quarter cell inside material by the snapshot's rays (either all four rays around it in a
///    set hold it that deep, or the bilinear blend of their depths says so on a smooth face), the move
///    is cut there (bisection). A cut move to a proposal on this tick's plane where the whole tool is
///    free (none of those points inside) is taken whole: the straight chord cuts a curved surface that
///    the constrained path runs along (Zilles & Salisbury's god-object slides along the surface to the
///    point nearest the HIP), so a proxy that fell behind a fast hand, or behind material the snapshot
///    has not yet seen cut, returns to the surface over the HIP instead of staying behind. Otherwise the
///    rest of the move is tried one axis at a time, so the proxy slides along walls and into concave
///    corners instead of stopping dead. A cut move (`held`) is a contact
///    whose force is the spring kp*(proxy - hip) plus damping along it. Points that start inside
///    material are not guarded: a HIP that starts inside (first update, or material added over a free tool)
///    feels nothing until it leaves; a tool in contact when material is added over it is pushed out (step 10).
/// 8. Force: f_n = max(0, kp*depth + kd*v_n), v_n the HIP's velocity into the surface (step 11), along the
///    shaded normal (force shading, force_shading.hpp: barycentric blend of the vertex normals at the triangle's three dexel
///    ends, so the direction does not jump between triangles; the triangle's own normal when
///    force_shading is off), plus the tangential friction spring kp*(proxy - frictionless proxy)
///    rotated into the shaded frame, plus, when cutting, the specific-cutting-force reaction
///    (cutting_force.hpp) against the HIP's velocity.
/// 9. Release: a plane whose HIP and deepest tool point (hip - r*n) are both clearly out of material (every ray
///    around each, in every set whose window covers it, has it more than a window spacing outside), or no plane
///    and a tool clearly out of material at its centre and six axis points, gives no contact and no guard: the
///    proxy joins the HIP in that tick, whatever lies between them. A hand that jumped across a thin wall or left
///    the far side of a deep cut is never left behind (a mouse or tracker has no force to stop it).
/// 10. Search again (constraint_plane.hpp, reacquire_plane): while in contact, when no plane is found (or only last
///    tick's is kept, or the HIP lies deeper than r + 2 window spacings behind the plane, or deeper than r + half a
///    spacing while the snapshot's readings hold it outside material), or when the guard holds the
///    proxy farther than r + half a window spacing from the HIP (in contact or not), the plane is
///    searched for again from reference points lifted out of material: along the last contact normal first (its
///    plane kept when it faces the same way), else along the six axis directions past the material the rays hold the
///    HIP in, taking the plane nearest the HIP on which the whole tool is free and which holds the HIP no deeper
///    than r + its nearest way out of material along an axis + a spacing (a deeper one is the workpiece's far
///    side, not the surface nearest the HIP). The proxy goes there at once (Zilles
///    & Salisbury's god-object rests on the surface point nearest the HIP), so it follows a hand that moved to
///    another face, or a surface changed under it (undo, union, a cut the snapshot catches up with), instead of
///    staying where the straight path was cut. While held that far with no plane found and
///    the tool free at the HIP, the proxy joins the HIP.
/// 11. No spike: the damping term of step 8 acts on the HIP's velocity into the surface (clamped to 2 m/s), not on the
///    depth's change, so a surface that moves under a still hand or a proxy that jumps adds none; and the force's
///    magnitude may rise per tick, while in contact, by at most what the hand explains (k times the HIP's move into the surface, plus
///    kd times its speed into it) plus 100 N/s x dt (0.1 N at 1 kHz), so a jump to the surface nearest the HIP, or material added over a still tool, brings its force in
///    over tens of ms. A force that falls falls at once.
/// 12. Never farther than it must be: when, after all that, the proxy stands more than r from a HIP the snapshot reads
///    outside material (so in contact: a proxy that far is held or on a plane), the plane chosen is not the surface
///    nearest the HIP (one plane at a time at a concave spot, a face the guarded path was cut at). Ball centres around
///    the HIP are tried (snapshot_depth.hpp, free_centre_within_radius: the HIP, then points at r, r/4, r/2 and 3r/4
///    along 26 directions, else the points of a lattice of spacing r/6 within r, nearest first; a ball free by the
///    rays under it, ball_free, and reached from the proxy by a straight
///    path that crosses no material, so a proxy keeps the side of a thin wall it entered from): the nearest free one
///    found takes the proxy, held there by the spring (the HIP itself: no contact). The spring is then shorter than
///    the one it replaces; a rise on later ticks is limited by step 11. Where none is found one radius out (a ball
///    pressed into a groove narrower than itself) the proxy stays.
/// Otherwise (no contact, no usable snapshot, or no window covering the HIP: a hand faster than the snapshot
/// follows) proxy = hip and the force is zero; in the last case the contact is kept for step 10 once a snapshot
/// covers the HIP again.
/// With r = 0 this is the point god-object. Behaviour to know:
/// - A HIP that goes through a slab thinner than its penetration (even in one tick) stays in contact
///   with the side it entered while the tool overlaps the slab or lies within a window spacing beyond it:
///   the proxy stays on that side and the force grows as kp*depth (the loop clamps it); once the tool is
///   clear of the far side by more than that, the contact is released (step 9).
/// - One plane at a time: at a concave corner the second face is felt through the guard (the proxy
///   stops at it, the spring pulls the HIP back), not as a second plane it slides along.
/// - At a convex edge a point tool under a penetration deeper than a cell stays on the first face until
///   it reaches the edge, then jumps to the second face; a ball rolls round the edge (step 4) while its
///   centre is outside the material.
/// - The guard's quarter cell is measured along the rays; near edges it can read up to about a cell
///   shallow (random walks over a sphere, a slotted box and a thin plate: contact points at most
///   0.31 / 0.5 / 0.23 cell inside the exact solid, tests/haptics/test_contact_random_walk.cpp).
/// Window stride (ActiveSurface::Window::stride): "cell" above means the window's ray spacing
/// (stride x cell_m) for the lateral tolerances (locality 3 cells, crossing tolerance, guard margin and
/// step, blend spread): a strided snapshot resolves no finer than its spacing; depths stay exact along rays.
/// update() is allocation-free, lock-free and takes a few microseconds, whatever the model size (the
/// guard reads 4 rays per set per sample; its step is half a window spacing, which the publisher sizes by
/// the tool's extent, so the sample count depends on the tool, not on the lattice).
class GodObject {
public:
    /// Throws tridex::Error naming the field when a parameter is negative or not finite, when
    /// dynamic_friction > static_friction, or when cutting_fade_speed_m_per_s is not > 0.
    explicit GodObject(ContactParams params);

    /// One contact update for the HIP at hip_m (world m) against the snapshot `surface`; dt_s (s) is the
    /// time since the previous update (the damping and cutting terms are dropped when dt_s is not > 0).
    /// A non-finite HIP gives no contact, zero force, and resets the god-object.
    ContactResult update(const ActiveSurface& surface, const Vec3& hip_m, double dt_s);
    /// Forgets the proxy and contact history (the next update starts free, with the proxy on the HIP).
    void reset();
    /// Changes the ball radius around the HIP (ContactParams::tool_radius_m, m) and resets the god-object.
    /// Allocation-free. A radius that is negative or not finite is ignored (returns false).
    bool set_tool_radius(double radius_m);
    /// The parameters.
    const ContactParams& params() const { return params_; }

private:
    // The proxy proposed on a plane (friction cone applied unless `frictionless`; the HIP when no plane was found), and
    // the material touched.
    struct Proposal {
        Vec3 proxy_m{0.0};
        Vec3 frictionless_m{0.0};
        bool sliding = false;
        std::uint8_t material = 0;
    };
    Proposal propose(const contact::PlaneSearch& plane, const Vec3& hip, const Vec3& proxy, bool frictionless) const;
    // Step 10's search after a held move and step 12: moves the proxy `next` (with the plane, proposal, constraint
    // normal n_c and hold that go with it) nearer the HIP when it ended farther than it needs to.
    void catch_up(const ActiveSurface& surface, const Vec3& hip, const Vec3& proxy, bool hip_inside, double held_lag_m,
                  contact::PlaneSearch& plane, Proposal& pr, Vec3& n_c, bool& held, Vec3& next);
    // Keeps what the next update reads: the result r for the HIP `hip`, the constraint normal n_c, the force's
    // normal n, whether the guard held the proxy, the plane and the material touched.
    void remember(const ContactResult& r, const Vec3& hip, const Vec3& n_c, const Vec3& n, bool held,
                  const contact::PlaneSearch& plane, std::uint8_t mat_id);
    // The material of id `id` (the table's entry, or the one of the ContactParams fields).
    const Material& material(std::uint8_t id) const;

    ContactParams params_;
    Material uniform_;  // the material of the ContactParams fields
    bool has_proxy_ = false;
    bool in_contact_ = false;
    bool sliding_ = false;
    Vec3 proxy_{0.0};
    Vec3 hip_{0.0};  // the HIP of the last update
    Vec3 normal_{0.0};             // contact normal (constraint normal, else the held spring's direction)
    Vec3 constraint_normal_{0.0};  // normal of the plane the contact point was taken on, zero when none
    Vec3 contact_point_{0.0};      // the last contact point, m
    int last_axis_ = 2;
    std::uint8_t material_ = 0;
    bool has_plane_ = false;  // the last tick's contact came from the plane (plane_q_, plane_n_)
    Vec3 plane_q_{0.0};       // a point of that plane, m
    Vec3 plane_n_{0.0};       // its outward unit normal
    int plane_axis_ = -1;     // its ray set
    Vec3 force_{0.0};         // the force of the last update, N
    // Step 12's lattice search found no free centre for the HIP lattice_miss_hip_ in the snapshot lattice_miss_seq_:
    // it is not run again until the HIP moves a lattice step, the snapshot changes or kLatticeRetryTicks pass (a
    // ball held in a groove narrower than itself pays for it once, not every tick).
    static constexpr int kLatticeRetryTicks = 16;
    bool lattice_miss_ = false;
    Vec3 lattice_miss_hip_{0.0};
    std::uint64_t lattice_miss_seq_ = 0;
    int lattice_miss_ticks_ = 0;
};

}  // namespace tridex::haptics
