// haptics/god_object.cpp - god-object contact on the constraint plane: the guarded move, the force.
#include "haptics/god_object.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "haptics/constraint_plane.hpp"
#include "haptics/forces/cutting_force.hpp"
#include "haptics/forces/force_shading.hpp"
#include "haptics/forces/friction.hpp"
#include "haptics/snapshot_depth.hpp"

namespace tridex::haptics {

namespace {

using namespace contact;

constexpr double kGuardStepCells = 0.5;  // sampling step of the guarded move, cells
constexpr int kGuardMaxSamples = 32;     // longer moves are sampled more coarsely
constexpr int kGuardBisections = 10;     // clipped position within 2^-10 of a sample step
// A HIP deeper than the tool's radius plus this many window spacings behind its plane: the surface nearest the HIP
// is searched for again.
constexpr double kLagCells = 2.0;
// A proxy held by the guard farther than the tool's radius plus this many window spacings from the HIP lags it too:
// a hand outside material is never left more than about a radius from its proxy.
constexpr double kHeldLagCells = 0.5;
// Slew limit of the force's rise beyond what the hand explains, N/s: a force may rise per tick by the spring's share of
// the HIP's move into the surface, plus this times dt. A proxy that jumps (to the surface nearest the HIP) or a
// surface that changes under a still tool (material added over it) then brings its force in over tens of ms.
constexpr double kRiseSlewNPerS = 100.0;
// The HIP's speed into the surface that the damping term uses is clamped to this (m/s): a HIP that jumps (a mouse's
// target, a tracker's glitch) must not turn damping into a spike.
constexpr double kMaxDampedSpeed = 2.0;

void require_non_negative(double v, const char* field) {
    if (!(std::isfinite(v) && v >= 0.0))
        throw Error(std::string("ContactParams.") + field + " = " + std::to_string(v) + " must be finite and >= 0");
}

// The largest fraction f in [0, 1] of the straight move a -> b (m) such that the move up to f stays out
// of material, sampled every step_m (at least kGuardStepCells window ray spacings) and refined by
// bisection; `a` must be outside material.
double free_fraction(const ActiveSurface& s, const Vec3& a, const Vec3& b, double step_m) {
    const double cells = glm::length(b - a) / std::max(step_m, kGuardStepCells * spacing_m(s)) * kGuardStepCells;
    if (!(cells > 0.0)) return 1.0;
    const int n = std::clamp(static_cast<int>(std::ceil(cells / kGuardStepCells)), 1, kGuardMaxSamples);
    double lo = 0.0;
    for (int i = 1; i <= n; ++i) {
        const double f = static_cast<double>(i) / n;
        if (!inside_material(s, a + f * (b - a))) {
            lo = f;
            continue;
        }
        double hi = f;
        for (int k = 0; k < kGuardBisections; ++k) {
            const double mid = 0.5 * (lo + hi);
            if (inside_material(s, a + mid * (b - a))) hi = mid;
            else lo = mid;
        }
        return lo;
    }
    return 1.0;
}

// The largest fraction of `move` that the tool can make from `at` without entering material: its centre,
// and for a ball (radius > 0) its six points at +-radius along the axes and, when with_contact, its
// contact point at - offset. A point already inside material at the start is not guarded.
// Sampling step: half a cell for a point tool; for a ball, also at most a quarter of its radius, so the
// cost does not grow with the resolution (a ball jumps over nothing thinner than r/4 unless it moves r/4
// in one tick: 2 mm for an 8 mm ball, i.e. 2 m/s at 1 kHz, above the safety stage's speed limit).
double guarded_fraction(const ActiveSurface& s, const Vec3& at, const Vec3& move, double radius, const Vec3& offset,
                        bool with_contact) {
    const double step_m = 0.25 * radius;
    double f = 1.0;
    if (!inside_material(s, at)) f = free_fraction(s, at, at + move, step_m);
    if (radius > 0.0) {
        if (with_contact && f > 0.0 && !inside_material(s, at - offset))
            f = free_fraction(s, at - offset, at - offset + f * move, step_m) * f;
        for (int i = 0; i < 6 && f > 0.0; ++i) {
            Vec3 p = at;
            p[i >> 1] += (i & 1) ? -radius : radius;
            if (!inside_material(s, p)) f = free_fraction(s, p, p + f * move, step_m) * f;
        }
    }
    return f;
}

/// The guard (step 7 of the class comment): the proxy moved from `proxy` towards `proposal` (m) without entering
/// material. When the straight move is cut and the proposal comes from a constraint plane (`on_plane`) on which the
/// tool is free, the proxy takes it: the straight chord cuts a curved surface the constrained path runs along, so
/// a proxy that fell behind (a fast hand, a cut the snapshot has not caught up with) returns to the surface point
/// nearest the HIP instead of staying behind for good. Otherwise the rest of the move is tried one axis at a time
/// (largest first), each step guarded, so the proxy runs along a wall or into a concave corner instead of stopping
/// dead, and `held` is set.
Vec3 guarded_move(const ActiveSurface& surface, const Vec3& proxy, const Vec3& proposal, double radius, const Vec3& offset,
                  bool with_contact, bool on_plane, bool& held) {
    const Vec3 move = proposal - proxy;
    const double f = guarded_fraction(surface, proxy, move, radius, offset, with_contact);
    if (f >= 1.0) return proposal;
    if (on_plane && pose_free(surface, proposal, radius, offset, with_contact)) return proposal;
    held = true;
    Vec3 next = proxy + f * move;
    const Vec3 rest = (1.0 - f) * move;
    int order[3];
    axis_order(rest, 0, order);
    for (int i = 0; i < 3; ++i) {
        Vec3 step(0.0);
        step[order[i]] = rest[order[i]];
        if (step == Vec3(0.0)) continue;
        next += guarded_fraction(surface, next, step, radius, offset, with_contact) * step;
    }
    return next;
}

// The force's frame: the constraint normal n (the held spring's direction when held), the shaded normal the force
// acts along (force shading, force_shading.hpp), the friction spring's offset rotated into it, and the depth (m).
struct ForceFrame {
    Vec3 n{0.0}, shaded{0.0}, tangential{0.0};
    double depth_m = 0.0;
};
ForceFrame force_frame(const ActiveSurface& surface, const PlaneSearch& plane, int axis, bool held, const Vec3& next,
                       const Vec3& hip, const Vec3& frictionless, bool shading) {
    ForceFrame f;
    if (held) {
        const Vec3 d = next - hip;
        const double len = glm::length(d);
        if (len > 0.0) {
            f.n = f.shaded = d / len;
            f.depth_m = len;
        }
        return f;
    }
    if (!plane.found) return f;
    const Triangle& tri = plane.tri;
    f.n = f.shaded = tri.n;
    f.depth_m = plane.depth;
    f.tangential = next - frictionless;
    if (!shading || plane.kept || plane.feature) return f;
    Vec3 vn[3];
    for (int i = 0; i < 3; ++i) vn[i] = dexel_end_normal(surface, axis, tri.iu[i], tri.iv[i], tri.depth[i], tri.exit[i]);
    const Vec3 b = blend_normals(vn, tri.w);
    // A blend that turns far from the plane means the vertex estimates are not of this face.
    if (glm::dot(b, f.n) > 0.5) {
        f.tangential = rotate_between(f.n, b, f.tangential);
        f.shaded = b;
    }
    return f;
}

}  // namespace

GodObject::GodObject(ContactParams params) : params_(std::move(params)) {
    require_non_negative(params_.tool_radius_m, "tool_radius_m");
    require_non_negative(params_.cutting_coefficient_n_per_m2, "cutting_coefficient_n_per_m2");
    if (!(std::isfinite(params_.cutting_fade_speed_m_per_s) && params_.cutting_fade_speed_m_per_s > 0.0))
        throw Error("ContactParams.cutting_fade_speed_m_per_s = " + std::to_string(params_.cutting_fade_speed_m_per_s) +
                    " must be finite and > 0");
    uniform_ = Material{params_.stiffness_n_per_m, params_.damping_n_s_per_m, params_.static_friction,
                        params_.dynamic_friction};
    validate_material(uniform_, "ContactParams");
}

void GodObject::remember(const ContactResult& r, const Vec3& hip, const Vec3& n_c, const Vec3& n, bool held,
                         const PlaneSearch& plane, std::uint8_t mat_id) {
    force_ = r.force_n;
    has_proxy_ = true;
    proxy_ = r.proxy_m;
    hip_ = hip;
    in_contact_ = r.contact;
    sliding_ = r.sliding;
    normal_ = r.contact ? (n_c != Vec3(0.0) ? n_c : n) : Vec3(0.0);
    constraint_normal_ = r.contact ? n_c : Vec3(0.0);
    contact_point_ = r.contact_point_m;
    has_plane_ = r.contact && plane.found && !held;
    if (has_plane_) {
        plane_q_ = plane.tri.on;
        plane_n_ = plane.tri.n;
        plane_axis_ = r.axis;
    }
    if (r.contact) {
        material_ = mat_id;
        if (r.axis >= 0) last_axis_ = r.axis;
    }
}

GodObject::Proposal GodObject::propose(const PlaneSearch& plane, const Vec3& hip, const Vec3& proxy,
                                       bool frictionless) const {
    Proposal p;
    p.proxy_m = hip;
    p.material = material_;
    if (!plane.found) return p;
    const Triangle& tri = plane.tri;
    // Material of the touched interval: the vertex with the largest barycentric weight.
    if (!plane.kept) {
        const int best = tri.w[0] >= tri.w[1] ? (tri.w[0] >= tri.w[2] ? 0 : 2) : (tri.w[1] >= tri.w[2] ? 1 : 2);
        p.material = tri.material[best];
    }
    const Material& mat = material(p.material);
    const double radius = params_.tool_radius_m;
    p.frictionless_m = hip + plane.depth * tri.n;
    p.proxy_m = p.frictionless_m;
    if (frictionless) return p;
    const Vec3 stick = proxy - (glm::dot(proxy - tri.on, tri.n) - radius) * tri.n;
    const FrictionStep f = friction_cone(stick, p.frictionless_m, plane.depth, mat.static_friction,
                                         mat.dynamic_friction, in_contact_ && sliding_);
    p.proxy_m = f.proxy_m;
    p.sliding = f.sliding;
    return p;
}

const Material& GodObject::material(std::uint8_t id) const {
    return params_.materials ? (*params_.materials)[id] : uniform_;
}

bool GodObject::set_tool_radius(double radius_m) {
    if (!(std::isfinite(radius_m) && radius_m >= 0.0)) return false;
    params_.tool_radius_m = radius_m;
    reset();
    return true;
}

void GodObject::reset() {
    has_proxy_ = false;
    in_contact_ = false;
    sliding_ = false;
    proxy_ = Vec3(0.0);
    hip_ = Vec3(0.0);
    normal_ = Vec3(0.0);
    constraint_normal_ = Vec3(0.0);
    contact_point_ = Vec3(0.0);
    last_axis_ = 2;
    material_ = 0;
    has_plane_ = false;
    plane_q_ = Vec3(0.0);
    plane_n_ = Vec3(0.0);
    plane_axis_ = -1;
    force_ = Vec3(0.0);
    lattice_miss_ = false;
}

void GodObject::catch_up(const ActiveSurface& surface, const Vec3& hip, const Vec3& proxy, bool hip_inside,
                         double held_lag_m, contact::PlaneSearch& plane, Proposal& pr, Vec3& n_c, bool& held,
                         Vec3& next) {
    const double radius = params_.tool_radius_m;
    // Held farther than the tool's radius and a few cells from the HIP, in contact or not: the guard stopped the proxy
    // on its way to a surface the HIP has moved to (step 10): take the surface nearest the HIP when the whole tool is
    // free there, or the HIP itself when no plane holds it back and the tool there is free.
    if (held && glm::length(next - hip) > held_lag_m) {
        const PlaneSearch again = reacquire_plane(surface, hip, radius, normal_, last_axis_, true);
        if (!again.found && pose_free(surface, hip, radius, Vec3(0.0), false)) {
            // No plane holds the HIP back and the tool there is free: the proxy joins it.
            plane = PlaneSearch{};
            pr = propose(plane, hip, proxy, true);
            n_c = Vec3(0.0);
            held = false;
            next = hip;
        } else if (again.found && again.depth < glm::length(next - hip)) {
            plane = again;
            pr = propose(plane, hip, proxy, true);
            n_c = plane.tri.n;
            held = false;
            next = pr.proxy_m;
        }
    }
    // Still farther than the radius from a HIP outside material (step 12): the plane chosen is not the surface nearest
    // the HIP (a concave spot where one plane at a time cannot hold the ball, a face the path was cut at). The force
    // then falls (the spring is shorter than the one the rules above gave); a rise later is limited by step 11.
    // Where a free ball centre lies within the radius, the proxy goes to the nearest one found, held there by the
    // spring; where none does (a ball pressed into a groove narrower than itself), the proxy stays.
    // Where none of the 26 directions one radius out is free, a lattice within the radius is searched, unless it
    // found nothing for nearly the same HIP in the same snapshot (lattice_miss_).
    if (!(radius > 0.0) || hip_inside || !(glm::length(next - hip) > radius)) return;
    const bool lattice = !lattice_miss_ || surface.sequence != lattice_miss_seq_ ||
                         glm::length(hip - lattice_miss_hip_) >= radius / contact::kLatticeSteps ||
                         lattice_miss_ticks_ >= kLatticeRetryTicks;
    Vec3 free_at(0.0);
    const bool found = free_centre_within_radius(surface, hip, radius, next, free_at, lattice);
    if (!found && lattice) {
        lattice_miss_ = true;
        lattice_miss_hip_ = hip;
        lattice_miss_seq_ = surface.sequence;
        lattice_miss_ticks_ = 0;
    } else if (!found) {
        ++lattice_miss_ticks_;
    } else {
        lattice_miss_ = false;
    }
    if (found) {
        plane = PlaneSearch{};
        pr = propose(plane, hip, proxy, true);
        const double len = glm::length(free_at - hip);
        n_c = len > 0.0 ? (free_at - hip) / len : Vec3(0.0);
        held = len > 0.0;
        next = free_at;
    }
}

ContactResult GodObject::update(const ActiveSurface& surface, const Vec3& hip, double dt_s) {
    ContactResult r;
    r.proxy_m = hip;
    r.contact_point_m = hip;
    if (!is_finite(hip)) {
        reset();
        return r;
    }
    const double radius = params_.tool_radius_m;
    const Vec3 proxy = has_proxy_ ? proxy_ : hip;
    const bool dt_ok = dt_s > 0.0 && std::isfinite(dt_s);
    const bool usable = surface.sequence != 0 && std::isfinite(surface.cell_m) && surface.cell_m > 0.0;
    // No window covers the HIP (a hand that moved faster than the snapshot follows it): nothing is known where
    // the tool is, so it feels nothing and the proxy waits on the HIP; the contact is kept so that the plane is
    // searched for again once a snapshot covers the HIP (step 10).
    if (usable && !covers(surface, hip)) {
        proxy_ = hip;
        hip_ = hip;
        has_proxy_ = true;
        contact_point_ = hip;
        has_plane_ = false;
        force_ = Vec3(0.0);
        return r;
    }
    if (usable) r.hip_inside = touches_material(surface, hip);
    PlaneSearch plane;
    if (usable)
        plane = search_plane(surface, hip, proxy, radius,
                             LastContact{in_contact_, normal_, contact_point_, last_axis_, has_plane_, plane_q_, plane_n_,
                                         plane_axis_});
    // A proxy that fell behind in contact (a hand faster than the proxy's path over a curved surface, a HIP moved
    // to another face, material added or removed under it) stands behind the faces around the HIP, which step 4
    // then refuses: search again from outside material (step 10).
    const bool may_reacquire = usable && in_contact_ && has_proxy_;
    // A plane the HIP lies deeper behind than the tool's radius and a few cells (a hand that went on through a thick
    // part) is searched for again too; a nearer plane replaces it (the normal's candidate keeps a thin wall's face).
    const double lag_m = radius + kLagCells * spacing_m(surface);
    bool reacquired = false;  // the plane was found again: the proxy's old place says nothing about friction on it
    // A HIP the snapshot's readings hold outside material cannot lie deeper than the tool's radius behind the
    // surface nearest it: a plane that says so is not that surface.
    const double held_lag_m = radius + kHeldLagCells * spacing_m(surface);
    const bool too_deep =
        plane.found && !plane.kept && (plane.depth > lag_m || (!r.hip_inside && plane.depth > held_lag_m));
    if (may_reacquire && (!plane.found || plane.kept || too_deep)) {
        const PlaneSearch again = reacquire_plane(surface, hip, radius, normal_, last_axis_, false);
        if (again.found && (!too_deep || again.depth < plane.depth)) {
            plane = again;
            reacquired = true;
        }
    }
    if (plane.found) r.axis = plane.axis;
    // A tool clearly out of material takes the proxy with it at once, whatever lies between them: a plane whose
    // HIP and deepest tool point (along -n) are both clearly outside is one the hand went through to free space (a
    // thin wall, the far side of a deep cut), and with no plane a free tool is not held back by the guard.
    bool released = false;
    if (plane.found && usable && has_proxy_ && clearly_outside(surface, hip) &&
        clearly_outside(surface, hip - radius * plane.tri.n)) {
        plane = PlaneSearch{};
        released = true;
    }
    const bool hip_free = released || (usable && has_proxy_ && !plane.found && tool_clearly_free(surface, hip, radius));
    Proposal pr = propose(plane, hip, proxy, reacquired);
    // Guard: move the proxy, and a ball's contact point, from last tick's position to the proposed one
    // without entering material. The contact point is the ball's point along -n_c, n_c the constraint
    // normal (this tick's plane, else last tick's); the centre when there is none or for a point tool.
    // A path whose start is already inside material is not guarded.
    Vec3 n_c = plane.found ? plane.tri.n : (in_contact_ ? constraint_normal_ : Vec3(0.0));
    bool held = false;
    Vec3 next = pr.proxy_m;
    if (usable && has_proxy_ && !hip_free)
        next = guarded_move(surface, proxy, pr.proxy_m, radius, radius * n_c, in_contact_ || plane.found, plane.found,
                            held);
    if (usable && has_proxy_) catch_up(surface, hip, proxy, r.hip_inside, held_lag_m, plane, pr, n_c, held, next);
    if (plane.found) r.axis = plane.axis;
    const Triangle& tri = plane.tri;
    const bool found = plane.found, kept = plane.kept;
    const Vec3 offset = radius * n_c;
    const Material& mat = material(pr.material);
    const std::uint8_t mat_id = pr.material;
    const Vec3 frictionless = pr.frictionless_m;
    bool sliding = pr.sliding;
    // Force.
    const double k = mat.stiffness_n_per_m;
    const ForceFrame fr = force_frame(surface, plane, r.axis, held, next, hip, frictionless, params_.force_shading);
    if (held) sliding = false;
    const Vec3 n = fr.n, shaded = fr.shaded, tangential = fr.tangential;
    const double depth_n = fr.depth_m;
    if (depth_n > 0.0) {
        // Damping on the HIP's velocity into the surface (Peng et al.: F = kp*dx + kd*v), so that a surface that
        // moves under a still hand, or a proxy that jumps, adds none.
        const double into = has_proxy_ && dt_ok ? -glm::dot(hip - hip_, shaded) / dt_s : 0.0;
        const double rate = std::clamp(into, -kMaxDampedSpeed, kMaxDampedSpeed);
        const double f = k * depth_n + mat.damping_n_s_per_m * rate;
        r.contact = true;
        r.proxy_m = next;
        r.normal = shaded;
        r.depth_m = depth_n;
        r.force_n = std::max(f, 0.0) * shaded + k * tangential;
        r.material = mat_id;
        r.sliding = sliding;
        r.held = held;
        r.contact_point_m = next - offset;
        if (params_.cutting && dt_ok && has_proxy_) {
            r.cutting_force_n = cutting_force(params_.cutting_coefficient_n_per_m2, radius, depth_n,
                                              (hip - hip_) / dt_s, shaded, params_.cutting_fade_speed_m_per_s);
            r.force_n += r.cutting_force_n;
        }
        // Only a rise is limited: a force that falls (the hand left the surface it pressed) falls at once.
        if (dt_ok && in_contact_) {
            const double most = glm::length(force_) + (k * dt_s + mat.damping_n_s_per_m) * std::max(0.0, rate) +
                                kRiseSlewNPerS * dt_s;
            const double now = glm::length(r.force_n);
            if (now > most) r.force_n *= most / now;
        }
        if (found) {
            r.plane_normal = tri.n;
            if (!kept) r.triangle_m = {tri.q[0], tri.q[1], tri.q[2]};
        } else {
            r.axis = -1;
        }
    } else {
        r.axis = -1;
    }
    remember(r, hip, n_c, n, held, plane, mat_id);
    return r;
}

}  // namespace tridex::haptics
