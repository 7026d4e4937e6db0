// compute/boolean.cpp - interval subtraction and the capsule (swept ball) subtraction over ray sets.
#include "compute/boolean.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "compute/capsule.hpp"
#include "core/error.hpp"

namespace tridex::compute {

bool subtract_interval_changed(std::vector<Interval>& ray, float t0, float t1) {
    if (!(t0 < t1)) return false;
    // First interval whose exit is beyond t0, and first one (from there) whose entry is at or past t1.
    auto first = std::upper_bound(ray.begin(), ray.end(), t0, [](float t, const Interval& iv) { return t < iv.exit; });
    auto last = std::lower_bound(first, ray.end(), t1, [](const Interval& iv, float t) { return iv.enter < t; });
    if (first == last) return false;  // no interval overlaps (t0, t1)
    // Pieces that survive on either side of the cut.
    const Interval head{first->enter, t0};
    const Interval tail{t1, std::prev(last)->exit};
    const bool keep_head = head.enter < head.exit, keep_tail = tail.enter < tail.exit;
    const auto at = ray.erase(first, last) - ray.begin();
    if (keep_tail) ray.insert(ray.begin() + at, tail);
    if (keep_head) ray.insert(ray.begin() + at, head);
    return true;
}

void subtract_interval(std::vector<Interval>& ray, float t0, float t1) { subtract_interval_changed(ray, t0, t1); }

BooleanStats subtract_capsule(TriDexel& model, const Segment& seg_m, double radius_m) {
    if (!is_finite(seg_m.a) || !is_finite(seg_m.b)) throw Error("subtract_capsule: tool segment is not finite");
    if (!std::isfinite(radius_m) || !(radius_m > 0.0))
        throw Error("subtract_capsule: tool radius must be a positive number of metres, got " + std::to_string(radius_m));
    const Lattice& L = model.lattice;
    const Vec3 ga = L.to_grid(seg_m.a), gb = L.to_grid(seg_m.b);
    const double gr = radius_m / L.cell_m;
    const Vec3 lo = glm::min(ga, gb) - Vec3(gr), hi = glm::max(ga, gb) + Vec3(gr);
    // Tool in float, relative to its start (the local origin).
    const glm::vec3 a_rel(0.0f), b_rel(gb - ga);
    const float r = static_cast<float>(gr);
    BooleanStats stats;
    for (int ax = 0; ax < 3; ++ax) {
        RaySet& set = model.sets[ax];
        const int ua = (ax + 1) % 3, va = (ax + 2) % 3;
        // Node range of the footprint, computed in double and clamped before converting to int.
        const double u_lo = std::max(0.0, std::ceil(lo[ua])), u_hi = std::min(set.nu - 1.0, std::floor(hi[ua]));
        const double v_lo = std::max(0.0, std::ceil(lo[va])), v_hi = std::min(set.nv - 1.0, std::floor(hi[va]));
        if (u_lo > u_hi || v_lo > v_hi) continue;
        const float start_depth = static_cast<float>(ga[ax]);
        glm::vec3 d(0.0f);
        d[ax] = 1.0f;
        for (int v = static_cast<int>(v_lo); v <= static_cast<int>(v_hi); ++v) {
            for (int u = static_cast<int>(u_lo); u <= static_cast<int>(u_hi); ++u) {
                ++stats.rays_visited;
                glm::vec3 o(0.0f);  // the ray's point level with the tool start
                o[ua] = static_cast<float>(u - ga[ua]);
                o[va] = static_cast<float>(v - ga[va]);
                float t0, t1;
                if (!capsule_chord(o, d, a_rel, b_rel, r, t0, t1)) continue;
                if (subtract_interval_changed(set.ray(u, v), start_depth + t0, start_depth + t1)) ++stats.rays_changed;
            }
        }
    }
    if (stats.rays_changed > 0) model.mark_dirty(seg_m.bounds(radius_m));
    return stats;
}

}  // namespace tridex::compute
