// haptics/constraint_plane.cpp - active triangle, plane search and the search again from outside material.
#include "haptics/constraint_plane.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "haptics/convex_contact.hpp"
#include "haptics/local_surface.hpp"
#include "haptics/snapshot_depth.hpp"

namespace tridex::haptics::contact {

namespace {

// Locality of an active triangle: each of its three ends must lie within kLocalityCells plus
// kLocalitySlope times the lateral distance between the HIP and the reference (cells) of the reference
// along the ray. A triangle whose rays straddle a feature (a ray passing under a slot's floor next to
// rays that see its wall) picks an end of another surface far away; its plane is not a face.
constexpr double kLocalityCells = 3.0;
constexpr double kLocalitySlope = 2.0;
// A lagging proxy's search starts this far (cells) above the tool, past the material the rays hold the HIP in.
constexpr double kReacquireLiftCells = 2.0;

// The triangle's plane replaced by the tangent plane of the local surface fitted around the HIP, at the point nearest
// it (local_surface.hpp), when the fit holds: a flat triangle's normal is off by up to its size over the radius of
// curvature, its depth by the chord's sag.
// True when the fit held (the triangle then carries the fitted plane).
bool refine(const ActiveSurface& s, int a, const Vec3& hip, Triangle& t) {
    const bool exits = (t.exit[0] ? 1 : 0) + (t.exit[1] ? 1 : 0) + (t.exit[2] ? 1 : 0) >= 2;
    // The patch is centred where the HIP's foot point is expected (on the triangle's plane first), and moved to
    // the foot point found until it lies in the patch (a ball's centre stands off a tilted surface, its foot point
    // a few cells aside of its projection along the rays).
    Vec3 centre = hip - glm::dot(hip - t.q[0], t.n) * t.n;
    for (int attempt = 0; attempt < 3; ++attempt) {
        SurfacePoint sp;
        if (!nearest_on_local_surface(s, a, hip, centre, t.q[0], t.n, exits, sp)) {
            // Outside the patch: try again around the foot point the fit gave, if it gave one.
            if (sp.normal == Vec3(0.0)) return false;
            centre = sp.point_m;
            continue;
        }
        t.on = sp.point_m;
        t.n = sp.normal;
        return true;
    }
    return false;
}

// True when plane p explains the material the ball of radius r about the HIP touches: none of its 26 points
// (convex_contact.hpp) that the plane holds more than half a window spacing outside reads inside material. At a
// convex edge a plane of one face leaves the other face's material unexplained.
bool explains_ball(const ActiveSurface& s, const Vec3& hip, double radius, const PlaneSearch& p) {
    const double margin = 0.5 * spacing_m(s);
    for (const Vec3& u : ball_directions()) {
        const Vec3 q = hip + radius * u;
        if (glm::dot(q - p.tri.on, p.tri.n) > margin && touches_material(s, q)) return false;
    }
    return true;
}

}  // namespace

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
    t.on = t.q[0];
    return true;
}

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
    bool refined = false;
    for (int pass = 0; pass < passes && !p.found; ++pass) {
        const Vec3& at = pass == 0 ? hip : reference;
        for (int k = 0; k < 3 && !p.found; ++k) {
            // While free the reference is the last HIP, up to a tick's motion (and, for a ball, its radius over the
            // cosine of the surface's tilt to the rays: two radii up to 60 degrees) away from the surface it crossed
            // along the ray; in contact it is on the surface.
            const double extra =
                last.in_contact ? 0.0 : (std::abs(hip[order[k]] - reference[order[k]]) + 2.0 * radius) / surface.cell_m;
            if (!active_triangle(surface, order[k], at, reference, extra, p.tri)) continue;
            refined = refine(surface, order[k], hip, p.tri);
            p.depth = radius - glm::dot(hip - p.tri.on, p.tri.n);
            if (!(p.depth > 0.0)) continue;
            // Constraint test: the god-object must not already have been behind this plane.
            const double proxy_depth = radius - glm::dot(proxy - p.tri.on, p.tri.n);
            if (proxy_depth > kCrossingToleranceCells * surface.window_spacing_cells(order[k]) * surface.cell_m) continue;
            p.found = true;
            p.axis = order[k];
        }
    }
    // A ball near a convex edge or corner: no face under its centre, or a triangle the local surface does not fit
    // (one that spans the edge): the tangent plane of the solid grown by the radius there.
    if (radius > 0.0 && !(p.found && refined && explains_ball(surface, hip, radius, p))) {
        PlaneSearch feature;
        if (convex_feature_plane(surface, hip, proxy, radius, p.found ? 2 : 1, feature)) return feature;
    }
    // No triangle, but the HIP is still inside material and behind the last plane: keep that plane.
    // A face's band between its last complete triangle and its edge (up to a cell wide) has no
    // triangle of its own; without this the proxy would fall off the face there.
    if (!p.found && last.in_contact && last.has_plane && read_depth(surface, hip).vouched > 0.0) {
        p.depth = radius - glm::dot(hip - last.plane_q, last.plane_n);
        if (p.depth > 0.0) {
            p.found = p.kept = true;
            p.tri.q[0] = p.tri.q[1] = p.tri.q[2] = p.tri.on = last.plane_q;
            p.tri.n = last.plane_n;
            p.axis = last.plane_axis;
        }
    }
    return p;
}

PlaneSearch reacquire_plane(const ActiveSurface& surface, const Vec3& hip, double radius, const Vec3& last_normal,
                            int last_axis, bool only_free) {
    const double lift = radius + kReacquireLiftCells * surface.cell_m;
    const auto search_from = [&](const Vec3& lifted) {
        return search_plane(surface, hip, lifted, radius,
                            LastContact{false, Vec3(0.0), lifted, last_axis, false, Vec3(0.0), Vec3(0.0), -1});
    };
    const auto free_on = [&](const PlaneSearch& p) {
        return pose_free(surface, hip + p.depth * p.tri.n, radius, radius * p.tri.n, true);
    };
    // The surface nearest the HIP is no farther from it than the nearest way out of material along an axis (each
    // ends on the surface): a plane that holds the HIP deeper than the radius and that way out (and a spacing, the
    // rays' lateral offset) is a face beyond it (the far side of the workpiece), not the surface nearest the HIP.
    double way_out = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 6; ++i) {
        const double out = exit_distance_m(surface, hip, i >> 1, (i & 1) ? -1 : 1);
        if (out >= 0.0) way_out = std::min(way_out, out);
    }
    const double deepest = radius + way_out + spacing_m(surface);
    const auto near_enough = [&](const PlaneSearch& p) { return p.found && p.depth <= deepest; };
    PlaneSearch same;  // the plane found from above the last contact normal, facing the same way
    if (last_normal != Vec3(0.0)) {
        same = search_from(hip + lift * last_normal);
        if (!near_enough(same) || !(glm::dot(same.tri.n, last_normal) > 0.0)) same = PlaneSearch{};
        if (same.found && free_on(same)) return same;
    }
    PlaneSearch best;
    for (int i = 0; i < 6; ++i) {
        const int axis = i >> 1, sign = (i & 1) ? -1 : 1;
        const double out = exit_distance_m(surface, hip, axis, sign);
        if (out < 0.0) continue;  // no window of this set covers the HIP
        Vec3 lifted = hip;
        lifted[axis] += sign * (out + lift);
        const PlaneSearch p = search_from(lifted);
        // Without a free pose to insist on, a face turned away from the one last touched is the far side of
        // what the hand pressed into (a thin wall, a tube's wall): not taken.
        const bool facing = only_free || last_normal == Vec3(0.0) || glm::dot(p.tri.n, last_normal) > 0.0;
        if (near_enough(p) && facing && (!best.found || p.depth < best.depth) && free_on(p)) best = p;
    }
    return best;
}

}  // namespace tridex::haptics::contact
