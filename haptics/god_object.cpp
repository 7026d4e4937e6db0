// haptics/god_object.cpp - active triangle from three dexel points, god-object contact and force.
#include "haptics/god_object.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace tridex::haptics {

namespace {

// How far (in cells) the previous proxy may lie behind a candidate plane and still count as having been
// outside it: absorbs the small changes between neighbouring active triangles of one curved surface.
constexpr double kCrossingTolerance = 0.25;

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

}  // namespace

GodObject::GodObject(ContactParams params) : params_(params) {
    require_non_negative(params_.stiffness_n_per_m, "stiffness_n_per_m");
    require_non_negative(params_.damping_n_s_per_m, "damping_n_s_per_m");
    require_non_negative(params_.tool_radius_m, "tool_radius_m");
}

void GodObject::reset() {
    has_proxy_ = false;
    in_contact_ = false;
    proxy_ = Vec3(0.0);
    normal_ = Vec3(0.0);
    depth_ = 0.0;
    last_axis_ = 2;
}

bool GodObject::active_triangle(const ActiveSurface& s, int a, const Vec3& hip, const Vec3& reference, Vec3& q0,
                                Vec3& n) const {
    const ActiveSurface::Window& w = s.sets[a];
    if (w.nu < 2 || w.nv < 2 || w.nu > ActiveSurface::kWindow || w.nv > ActiveSurface::kWindow) return false;
    const int ua = (a + 1) % 3, va = (a + 2) % 3;
    // HIP projection in window-local grid units (u, v).
    const double fu = (hip[ua] - s.origin_m[ua]) / s.cell_m - w.u0;
    const double fv = (hip[va] - s.origin_m[va]) / s.cell_m - w.v0;
    if (!(fu >= 0.0 && fu <= w.nu - 1 && fv >= 0.0 && fv <= w.nv - 1)) return false;  // also rejects NaN
    const int iu = std::min(static_cast<int>(fu), w.nu - 2);
    const int iv = std::min(static_cast<int>(fv), w.nv - 2);
    // Split the cell along its (0,0)-(1,1) diagonal; take the half holding the HIP.
    const bool lower = (fu - iu) >= (fv - iv);
    // Lower half: (0,0), (1,0), (1,1); upper half: (0,0), (1,1), (0,1).
    const int cu[3] = {iu, iu + 1, lower ? iu + 1 : iu};
    const int cv[3] = {iv, lower ? iv : iv + 1, iv + 1};
    const double ref = (reference[a] - s.origin_m[a]) / s.cell_m;  // grid units along the axis
    Vec3 q[3];
    int exits = 0;
    for (int k = 0; k < 3; ++k) {
        const int c = std::min(w.intervals(cu[k], cv[k]), ActiveSurface::kMaxIntervals);
        if (c == 0) return false;
        double best = std::numeric_limits<double>::infinity();
        double depth = 0.0;
        bool is_exit = false;
        for (int i = 0; i < c; ++i) {
            const double x = w.exit(cu[k], cv[k], i);
            const double e = w.enter(cu[k], cv[k], i);
            if (std::abs(x - ref) < best) {  // exit first: on a tie the exit end wins
                best = std::abs(x - ref);
                depth = x;
                is_exit = true;
            }
            if (std::abs(e - ref) < best) {
                best = std::abs(e - ref);
                depth = e;
                is_exit = false;
            }
        }
        q[k] = s.point(a, w.u0 + cu[k], w.v0 + cv[k], depth);
        exits += is_exit ? 1 : 0;
    }
    Vec3 nn = glm::cross(q[1] - q[0], q[2] - q[0]);
    const double len = glm::length(nn);
    if (!(len > 0.0) || !std::isfinite(len)) return false;  // only with corrupt depths (NaN, inf)
    nn /= len;
    const bool outward_positive = exits >= 2;
    if ((nn[a] > 0.0) != outward_positive) nn = -nn;
    q0 = q[0];
    n = nn;
    return true;
}

ContactResult GodObject::update(const ActiveSurface& surface, const Vec3& hip, double dt_s) {
    ContactResult r;
    r.proxy_m = hip;
    if (!is_finite(hip)) {
        reset();
        return r;
    }
    const Vec3 proxy = has_proxy_ ? proxy_ : hip;
    const bool usable = surface.sequence != 0 && std::isfinite(surface.cell_m) && surface.cell_m > 0.0;
    if (usable) {
        const Vec3 dir = in_contact_ ? normal_ : hip - proxy;
        const Vec3 reference = in_contact_ ? proxy - params_.tool_radius_m * normal_ : proxy;
        int order[3];
        axis_order(dir, last_axis_, order);
        for (int k = 0; k < 3 && !r.contact; ++k) {
            Vec3 q0, n;
            if (!active_triangle(surface, order[k], hip, reference, q0, n)) continue;
            const double depth = params_.tool_radius_m - glm::dot(hip - q0, n);
            if (!(depth > 0.0)) continue;
            // Constraint test: the god-object must not already have been behind this plane.
            const double proxy_depth = params_.tool_radius_m - glm::dot(proxy - q0, n);
            if (proxy_depth > kCrossingTolerance * surface.cell_m) continue;
            const double previous = in_contact_ ? depth_ : 0.0;
            const double rate = (dt_s > 0.0 && std::isfinite(dt_s)) ? (depth - previous) / dt_s : 0.0;
            const double f = params_.stiffness_n_per_m * depth + params_.damping_n_s_per_m * rate;
            r.proxy_m = hip + depth * n;
            r.force_n = std::max(f, 0.0) * n;
            r.normal = n;
            r.depth_m = depth;
            r.contact = true;
            r.axis = order[k];
        }
    }
    has_proxy_ = true;
    proxy_ = r.proxy_m;
    in_contact_ = r.contact;
    normal_ = r.normal;
    depth_ = r.depth_m;
    if (r.contact) last_axis_ = r.axis;
    return r;
}

}  // namespace tridex::haptics
