// haptics/god_object.cpp - active triangle from three dexel points, god-object contact, guard and force.
#include "haptics/god_object.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "haptics/cutting_force.hpp"
#include "haptics/force_shading.hpp"
#include "haptics/friction.hpp"

namespace tridex::haptics {

namespace {

// How far (in cells) the previous proxy may lie behind a candidate plane and still count as having been
// outside it: absorbs the small changes between neighbouring active triangles of one curved surface.
constexpr double kCrossingTolerance = 0.25;
// Guard: a point is inside material when read_depth() says it is deeper than this. Points on
// an active triangle of a smooth surface read a few hundredths of a cell deep (chord sag); triangles
// spanning a concave edge reach half a cell, so a quarter lets the proxy ride the triangles while
// stopping it before it sinks into material.
constexpr double kGuardMarginCells = 0.25;
// A tool is clearly free when every ray around each of its test points has the point more than this many window
// spacings outside material: then the proxy joins the HIP (clearly_outside). A spacing keeps the chord sag and
// the guard's margin of a surface the tool still touches well inside it.
constexpr double kFreeMarginCells = 1.0;
// Locality of an active triangle: each of its three ends must lie within kLocalityCells plus
// kLocalitySlope times the lateral distance between the HIP and the reference (cells) of the reference
// along the ray. A triangle whose rays straddle a feature (a ray passing under a slot's floor next to
// rays that see its wall) picks an end of another surface far away; its plane is not a face.
constexpr double kLocalityCells = 3.0;
constexpr double kLocalitySlope = 2.0;
constexpr double kGuardStepCells = 0.5;  // sampling step of the guarded move, cells
constexpr double kReacquireLiftCells = 2.0;  // a lagging proxy's search starts this far above the tool, cells
constexpr int kGuardMaxSamples = 32;     // longer moves are sampled more coarsely
constexpr int kGuardBisections = 10;     // clipped position within 2^-10 of a sample step

void require_non_negative(double v, const char* field) {
    if (!(std::isfinite(v) && v >= 0.0))
        throw Error(std::string("ContactParams.") + field + " = " + std::to_string(v) + " must be finite and >= 0");
}

// Axes ordered by |dir| component, largest first; `fallback` first when dir is zero.
void axis_order(const Vec3& dir, int fallback, int order[3]) {
    const double m[3] = {std::abs(dir.x), std::abs(dir.y), std::abs(dir.z)};
    if (!(m[0] > 0.0 || m[1] > 0.0 || m[2] > 0.0)) {
        order[0] = fallback;
        order[1] = (fallback + 1) % 3;
        order[2] = (fallback + 2) % 3;
        return;
    }
    order[0] = 0;
    order[1] = 1;
    order[2] = 2;
    // Three-element insertion sort, descending; stable so ties keep X, Y, Z order.
    for (int i = 1; i < 3; ++i)
        for (int j = i; j > 0 && m[order[j]] > m[order[j - 1]]; --j) std::swap(order[j], order[j - 1]);
}

bool window_ok(const ActiveSurface::Window& w) {
    return w.nu >= 2 && w.nv >= 2 && w.nu <= ActiveSurface::kWindow && w.nv <= ActiveSurface::kWindow && w.stride >= 1;
}

// Largest window ray spacing over the usable windows of `s`, m: the lateral resolution of the snapshot.
double spacing_m(const ActiveSurface& s) {
    int cells = 1;
    for (int a = 0; a < 3; ++a)
        if (window_ok(s.sets[a])) cells = std::max(cells, s.window_spacing_cells(a));
    return cells * s.cell_m;
}

// The active triangle on one ray set: three dexel ends (window-local ray indices, depth in grid units,
// end type, interval material), their world points, the outward unit normal and the HIP's barycentric
// coordinates in the triangle's cover.
struct Triangle {
    int iu[3], iv[3];
    double depth[3];
    bool exit[3];
    std::uint8_t material[3];
    Vec3 q[3];
    Vec3 n;
    double w[3];
};

bool active_triangle(const ActiveSurface& s, int a, const Vec3& hip, const Vec3& reference, double extra_reach_cells,
                     Triangle& t) {
    const ActiveSurface::Window& w = s.sets[a];
    if (!window_ok(w)) return false;
    const int ua = (a + 1) % 3, va = (a + 2) % 3;
    // HIP projection in window-local ray units (u, v).
    const ActiveSurface::WindowCoord c = s.to_window(a, hip);
    const double fu = c.fu, fv = c.fv;
    if (!(fu >= 0.0 && fu <= w.nu - 1 && fv >= 0.0 && fv <= w.nv - 1)) return false;  // also rejects NaN
    const int iu = std::min(static_cast<int>(fu), w.nu - 2);
    const int iv = std::min(static_cast<int>(fv), w.nv - 2);
    // Split the cell along its (0,0)-(1,1) diagonal; take the half holding the HIP.
    const double su = fu - iu, sv = fv - iv;
    const bool lower = su >= sv;
    // Lower half: (0,0), (1,0), (1,1); upper half: (0,0), (1,1), (0,1). Barycentric weights to match.
    const int cu[3] = {iu, iu + 1, lower ? iu + 1 : iu};
    const int cv[3] = {iv, lower ? iv : iv + 1, iv + 1};
    if (lower) {
        t.w[0] = 1.0 - su;
        t.w[1] = su - sv;
        t.w[2] = sv;
    } else {
        t.w[0] = 1.0 - sv;
        t.w[1] = su;
        t.w[2] = sv - su;
    }
    const double ref = s.to_window(a, reference).d;  // grid units along the axis
    // Locality: every end must lie within reach of the reference along the axis (see kLocalityCells; the
    // constant part scales with the window's ray spacing, as the ends lie up to a spacing from the HIP).
    const double du = (reference[ua] - hip[ua]) / s.cell_m, dv = (reference[va] - hip[va]) / s.cell_m;
    const double reach = kLocalityCells * s.window_spacing_cells(a) + kLocalitySlope * std::sqrt(du * du + dv * dv) +
                         extra_reach_cells;
    int exits = 0;
    for (int k = 0; k < 3; ++k) {
        const int c = std::min(w.intervals(cu[k], cv[k]), ActiveSurface::kMaxIntervals);
        if (c == 0) return false;
        double best = std::numeric_limits<double>::infinity();
        for (int i = 0; i < c; ++i) {
            const double x = w.exit(cu[k], cv[k], i);
            const double e = w.enter(cu[k], cv[k], i);
            if (std::abs(x - ref) < best) {  // exit first: on a tie the exit end wins
                best = std::abs(x - ref);
                t.depth[k] = x;
                t.exit[k] = true;
                t.material[k] = w.material_of(cu[k], cv[k], i);
            }
            if (std::abs(e - ref) < best) {
                best = std::abs(e - ref);
                t.depth[k] = e;
                t.exit[k] = false;
                t.material[k] = w.material_of(cu[k], cv[k], i);
            }
        }
        if (!(best <= reach)) return false;
        t.iu[k] = cu[k];
        t.iv[k] = cv[k];
        t.q[k] = s.window_point(a, cu[k], cv[k], t.depth[k]);
        exits += t.exit[k] ? 1 : 0;
    }
    Vec3 nn = glm::cross(t.q[1] - t.q[0], t.q[2] - t.q[0]);
    const double len = glm::length(nn);
    if (!(len > 0.0) || !std::isfinite(len)) return false;  // only with corrupt depths (NaN, inf)
    nn /= len;
    const bool outward_positive = exits >= 2;
    if ((nn[a] > 0.0) != outward_positive) nn = -nn;
    t.n = nn;
    return true;
}

// Signed distance (grid units) along ray (iu, iv) from depth d to the nearest interval end: positive
// inside an interval, negative outside; -kEmpty for an empty ray.
constexpr double kEmpty = 1e9;
double ray_signed_depth(const ActiveSurface::Window& w, int iu, int iv, double d) {
    const int c = std::min(w.intervals(iu, iv), ActiveSurface::kMaxIntervals);
    double best = -kEmpty;
    for (int i = 0; i < c; ++i) best = std::max(best, std::min(d - w.enter(iu, iv, i), w.exit(iu, iv, i) - d));
    return best;
}

// Two readings of how deep p lies inside material, in window ray spacings (grid units / the window's
// stride: the snapshot's lateral resolution), from the four rays around p's projection in each ray set
// (their signed depths c00..c11 along the rays):
// - vouched: a set vouches for the smallest of its four depths (all four rays hold p that far inside);
//   the largest depth any set vouches for. For a face square to a set it is the distance to the face;
//   near edges and on faces at 45 degrees to every set it reads shallow by up to about a spacing (a
//   corner ray sees another face), so it never calls a point of a face "inside".
// - blended: the bilinear blend of the four depths, from each set whose four rays are non-empty and
//   agree within kBlendSpreadCells spacings (one surface sheet; exact for a plane: the distance along
//   the set's axis); the shallowest over those sets (a distance along any axis bounds the distance to
//   the surface from above). Accurate on smooth faces at any angle; silent near edges.
// Both are -kEmpty when nothing is known (no window covers p, or no set qualifies).
constexpr double kBlendSpreadCells = 2.0;
struct DepthReading {
    double vouched = -kEmpty;
    double blended = -kEmpty;
};
DepthReading read_depth(const ActiveSurface& s, const Vec3& p) {
    DepthReading r;
    double blended = kEmpty;
    for (int a = 0; a < 3; ++a) {
        const ActiveSurface::Window& w = s.sets[a];
        if (!window_ok(w)) continue;
        const ActiveSurface::WindowCoord c = s.to_window(a, p);
        const double fu = c.fu, fv = c.fv;
        if (!(fu >= 0.0 && fu <= w.nu - 1 && fv >= 0.0 && fv <= w.nv - 1)) continue;
        const int iu = std::min(static_cast<int>(fu), w.nu - 2);
        const int iv = std::min(static_cast<int>(fv), w.nv - 2);
        const double c00 = ray_signed_depth(w, iu, iv, c.d), c10 = ray_signed_depth(w, iu + 1, iv, c.d);
        const double c01 = ray_signed_depth(w, iu, iv + 1, c.d), c11 = ray_signed_depth(w, iu + 1, iv + 1, c.d);
        const double lo = std::min(std::min(c00, c10), std::min(c01, c11));
        const double hi = std::max(std::max(c00, c10), std::max(c01, c11));
        if (lo <= -kEmpty) continue;  // an empty ray: this set vouches for nothing and does not blend
        const double per = 1.0 / s.window_spacing_cells(a);  // grid units -> ray spacings
        r.vouched = std::max(r.vouched, per * lo);
        if (per * (hi - lo) > kBlendSpreadCells) continue;
        const double su = fu - iu, sv = fv - iv;
        blended = std::min(blended, per * ((1.0 - sv) * ((1.0 - su) * c00 + su * c10) + sv * ((1.0 - su) * c01 + su * c11)));
    }
    if (blended < kEmpty) r.blended = blended;
    return r;
}

// The guard's test: inside when either reading says deeper than kGuardMarginCells.
bool inside_material(const ActiveSurface& s, const Vec3& p) {
    const DepthReading r = read_depth(s, p);
    return r.vouched > kGuardMarginCells || r.blended > kGuardMarginCells;
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

// True when p is clearly out of material: at least one ray set's window covers it, and in every set that does, each
// of the four rays around its projection has it more than kFreeMarginCells window spacings outside its intervals.
bool clearly_outside(const ActiveSurface& s, const Vec3& p) {
    bool covered = false;
    for (int a = 0; a < 3; ++a) {
        const ActiveSurface::Window& w = s.sets[a];
        if (!window_ok(w)) continue;
        const ActiveSurface::WindowCoord c = s.to_window(a, p);
        if (!(c.fu >= 0.0 && c.fu <= w.nu - 1 && c.fv >= 0.0 && c.fv <= w.nv - 1)) continue;
        const int iu = std::min(static_cast<int>(c.fu), w.nu - 2);
        const int iv = std::min(static_cast<int>(c.fv), w.nv - 2);
        const double limit = -kFreeMarginCells * s.window_spacing_cells(a);
        for (int k = 0; k < 4; ++k)
            if (ray_signed_depth(w, iu + (k & 1), iv + (k >> 1), c.d) > limit) return false;
        covered = true;
    }
    return covered;
}

// True when the tool at `at` is clearly out of material (clearly_outside): its centre and, for a ball, its six
// points at +-radius along the axes.
bool tool_clearly_free(const ActiveSurface& s, const Vec3& at, double radius) {
    if (!clearly_outside(s, at)) return false;
    for (int i = 0; i < 6 && radius > 0.0; ++i) {
        Vec3 p = at;
        p[i >> 1] += (i & 1) ? -radius : radius;
        if (!clearly_outside(s, p)) return false;
    }
    return true;
}

/// What the god-object kept from its last update that the plane search reads.
struct LastContact {
    bool in_contact;
    Vec3 normal;         // contact normal
    Vec3 contact_point;  // the last contact point, m
    int axis;            // ray set of the last contact
    bool has_plane;      // the last contact came from a plane (plane_q, plane_n, plane_axis)
    Vec3 plane_q, plane_n;
    int plane_axis;
};

/// The constraint plane of this update (steps 1-4 of the class comment): found, its triangle, the HIP's depth
/// behind it, its ray set; kept when it is last tick's plane (no triangle of its own).
struct PlaneSearch {
    Triangle tri{};
    bool found = false, kept = false;
    double depth = 0.0;
    int axis = -1;
};

PlaneSearch search_plane(const ActiveSurface& surface, const Vec3& hip, const Vec3& proxy, double radius,
                         const LastContact& last) {
    PlaneSearch p;
    const Vec3 dir = last.in_contact ? last.normal : hip - proxy;
    const Vec3 reference = last.in_contact ? last.contact_point : proxy;  // last tick's contact point
    int order[3];
    axis_order(dir, last.axis, order);
    // The triangle under the HIP first; while in contact, then the one under the proxy's contact
    // point when the HIP is inside material (a HIP deep under a curved surface has no face of the
    // proxy's side above it).
    const int passes = last.in_contact && inside_material(surface, hip) ? 2 : 1;
    for (int pass = 0; pass < passes && !p.found; ++pass) {
        const Vec3& at = pass == 0 ? hip : reference;
        for (int k = 0; k < 3 && !p.found; ++k) {
            // While free the reference is the last HIP, up to a tick's motion (and a ball's radius)
            // away from the surface it crossed; in contact it is on the surface.
            const double extra =
                last.in_contact ? 0.0 : (std::abs(hip[order[k]] - reference[order[k]]) + radius) / surface.cell_m;
            if (!active_triangle(surface, order[k], at, reference, extra, p.tri)) continue;
            p.depth = radius - glm::dot(hip - p.tri.q[0], p.tri.n);
            if (!(p.depth > 0.0)) continue;
            // Constraint test: the god-object must not already have been behind this plane.
            const double proxy_depth = radius - glm::dot(proxy - p.tri.q[0], p.tri.n);
            if (proxy_depth > kCrossingTolerance * surface.window_spacing_cells(order[k]) * surface.cell_m) continue;
            p.found = true;
            p.axis = order[k];
        }
    }
    // No triangle, but the HIP is still inside material and behind the last plane: keep that plane.
    // A face's band between its last complete triangle and its edge (up to a cell wide) has no
    // triangle of its own; without this the proxy would fall off the face there.
    if (!p.found && last.in_contact && last.has_plane && read_depth(surface, hip).vouched > 0.0) {
        p.depth = radius - glm::dot(hip - last.plane_q, last.plane_n);
        if (p.depth > 0.0) {
            p.found = p.kept = true;
            p.tri.q[0] = p.tri.q[1] = p.tri.q[2] = last.plane_q;
            p.tri.n = last.plane_n;
            p.axis = last.plane_axis;
        }
    }
    return p;
}

// True when the tool placed at `at` has none of the guard's points inside material: its centre and, for a ball, its
// contact point at - offset (when with_contact) and its six points at +-radius along the axes.
bool pose_free(const ActiveSurface& s, const Vec3& at, double radius, const Vec3& offset, bool with_contact) {
    if (inside_material(s, at)) return false;
    if (radius <= 0.0) return true;
    if (with_contact && inside_material(s, at - offset)) return false;
    for (int i = 0; i < 6; ++i) {
        Vec3 p = at;
        p[i >> 1] += (i & 1) ? -radius : radius;
        if (inside_material(s, p)) return false;
    }
    return true;
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
    depth_ = 0.0;
    last_axis_ = 2;
    material_ = 0;
    has_plane_ = false;
    plane_q_ = Vec3(0.0);
    plane_n_ = Vec3(0.0);
    plane_axis_ = -1;
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
    Vec3 frictionless(0.0);
    PlaneSearch plane;
    if (usable)
        plane = search_plane(surface, hip, proxy, radius,
                             LastContact{in_contact_, normal_, contact_point_, last_axis_, has_plane_, plane_q_, plane_n_,
                                         plane_axis_});
    // A proxy that fell behind in contact (a hand faster than the proxy's straight path over a curved surface, or
    // material the snapshot has not yet seen cut) stands behind the faces around the HIP, which step 4 then refuses:
    // search again from the HIP lifted out of the material along the last contact normal, and take a face under the
    // HIP that faces the same way as the one last touched (the far face of a thin wall faces the other way).
    if (usable && in_contact_ && has_proxy_ && (!plane.found || plane.kept) && normal_ != Vec3(0.0)) {
        const Vec3 lifted = hip + (radius + kReacquireLiftCells * surface.cell_m) * normal_;
        const PlaneSearch again = search_plane(surface, hip, lifted, radius,
                                               LastContact{false, Vec3(0.0), lifted, last_axis_, false, Vec3(0.0),
                                                           Vec3(0.0), -1});
        if (again.found && glm::dot(again.tri.n, normal_) > 0.0) plane = again;
    }
    Triangle& tri = plane.tri;
    bool& found = plane.found;
    bool& kept = plane.kept;
    double& depth = plane.depth;
    if (plane.found) r.axis = plane.axis;
    // A tool clearly out of material takes the proxy with it at once, whatever lies between them: a plane whose
    // HIP and deepest tool point (along -n) are both clearly outside is one the hand went through to free space (a
    // thin wall, the far side of a deep cut), and with no plane a free tool is not held back by the guard.
    bool released = false;
    if (found && usable && has_proxy_ && clearly_outside(surface, hip) && clearly_outside(surface, hip - radius * tri.n)) {
        found = kept = false;
        depth = 0.0;
        released = true;
    }
    const bool hip_free = released || (usable && has_proxy_ && !found && tool_clearly_free(surface, hip, radius));
    // Material of the touched interval: the vertex with the largest barycentric weight.
    std::uint8_t mat_id = material_;
    if (found && !kept) {
        const int best = tri.w[0] >= tri.w[1] ? (tri.w[0] >= tri.w[2] ? 0 : 2) : (tri.w[1] >= tri.w[2] ? 1 : 2);
        mat_id = tri.material[best];
    }
    const Material& mat = material(mat_id);
    // Proposed proxy: on the plane, friction cone applied; the HIP itself when there is no plane.
    Vec3 proposal = hip;
    bool sliding = false;
    if (found) {
        frictionless = hip + depth * tri.n;
        const Vec3 stick = proxy - (glm::dot(proxy - tri.q[0], tri.n) - radius) * tri.n;
        const FrictionStep f =
            friction_cone(stick, frictionless, depth, mat.static_friction, mat.dynamic_friction, in_contact_ && sliding_);
        proposal = f.proxy_m;
        sliding = f.sliding;
    }
    // Guard: move the proxy, and a ball's contact point, from last tick's position to the proposed one
    // without entering material. The contact point is the ball's point along -n_c, n_c the constraint
    // normal (this tick's plane, else last tick's); the centre when there is none or for a point tool.
    // A path whose start is already inside material is not guarded.
    const Vec3 n_c = found ? tri.n : (in_contact_ ? constraint_normal_ : Vec3(0.0));
    const Vec3 offset = radius * n_c;
    bool held = false;
    Vec3 next = proposal;
    if (usable && has_proxy_ && !hip_free)
        next = guarded_move(surface, proxy, proposal, radius, offset, in_contact_ || found, found, held);
    // Force.
    const double previous_depth = in_contact_ ? depth_ : 0.0;
    const double k = mat.stiffness_n_per_m;
    Vec3 n(0.0), shaded(0.0), tangential(0.0);
    double depth_n = 0.0;
    if (held) {
        const Vec3 d = next - hip;
        const double len = glm::length(d);
        if (len > 0.0) {
            n = d / len;
            shaded = n;
            depth_n = len;
        }
        sliding = false;
    } else if (found) {
        n = tri.n;
        depth_n = depth;
        tangential = next - frictionless;
        shaded = n;
        if (params_.force_shading && !kept) {
            Vec3 vn[3];
            for (int i = 0; i < 3; ++i)
                vn[i] = dexel_end_normal(surface, r.axis, tri.iu[i], tri.iv[i], tri.depth[i], tri.exit[i]);
            const Vec3 b = blend_normals(vn, tri.w);
            // A blend that turns far from the plane means the vertex estimates are not of this face.
            if (glm::dot(b, n) > 0.5) {
                tangential = rotate_between(n, b, tangential);
                shaded = b;
            }
        }
    }
    if (depth_n > 0.0) {
        const double rate = dt_ok ? (depth_n - previous_depth) / dt_s : 0.0;
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
        if (found) {
            r.plane_normal = tri.n;
            if (!kept) r.triangle_m = {tri.q[0], tri.q[1], tri.q[2]};
        } else {
            r.axis = -1;
        }
    } else {
        r.axis = -1;
    }
    has_proxy_ = true;
    proxy_ = r.proxy_m;
    hip_ = hip;
    in_contact_ = r.contact;
    sliding_ = r.sliding;
    normal_ = r.contact ? (n_c != Vec3(0.0) ? n_c : n) : Vec3(0.0);
    constraint_normal_ = r.contact ? n_c : Vec3(0.0);
    contact_point_ = r.contact_point_m;
    depth_ = r.depth_m;
    has_plane_ = r.contact && found && !held;
    if (has_plane_) {
        plane_q_ = tri.q[0];
        plane_n_ = tri.n;
        plane_axis_ = r.axis;
    }
    if (r.contact) {
        material_ = mat_id;
        if (r.axis >= 0) last_axis_ = r.axis;
    }
    return r;
}

}  // namespace tridex::haptics
