// compute/model/interval_ops.hpp - one ray's Boolean updates: subtract, union and paint a span [t0, t1].
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "compute/model/tridexel.hpp"

namespace tridex::compute {

/// The stretch of one ray (grid units along it) holding every interval end that operations on it added,
/// removed, moved or repainted: what TriDexel::mark_dirty must cover. Empty (lo > hi) until a change is added.
struct ChangedSpan {
    float lo = std::numeric_limits<float>::infinity();
    float hi = -std::numeric_limits<float>::infinity();
    /// Grows the span to hold [a, b] (a <= b).
    void add(float a, float b) {
        lo = std::min(lo, a);
        hi = std::max(hi, b);
    }
    /// True when no change was added (also when a bound is NaN).
    bool empty() const { return !(lo <= hi); }
};

/// The span of the ends that differ between two versions of one ray (`before`, `after`: sorted, disjoint
/// intervals): the hull of the ends outside their common leading and trailing ends (depth and material). Empty
/// when the two are equal. O(intervals).
ChangedSpan changed_span(const std::vector<Interval>& before, const std::vector<Interval>& after);

/// The box (grid units) of the interval ends changed on several rays: each changed ray adds its node and
/// its ChangedSpan. mark() marks it dirty (TriDexel::mark_dirty_grid); an empty box marks nothing.
struct ChangedBox {
    Vec3 lo{std::numeric_limits<double>::infinity()};
    Vec3 hi{-std::numeric_limits<double>::infinity()};
    /// Adds the changed ends `span` of the ray of set `axis` through node (u, v) (u along (axis+1)%3, v along (axis+2)%3).
    void add_ray(int axis, int u, int v, const ChangedSpan& span) {
        if (span.empty()) return;
        Vec3 a(0.0), b(0.0);
        a[axis] = span.lo;
        b[axis] = span.hi;
        a[(axis + 1) % 3] = b[(axis + 1) % 3] = u;
        a[(axis + 2) % 3] = b[(axis + 2) % 3] = v;
        lo = glm::min(lo, a);
        hi = glm::max(hi, b);
    }
    /// Grows this box to hold `other`.
    void add(const ChangedBox& other) {
        lo = glm::min(lo, other.lo);
        hi = glm::max(hi, other.hi);
    }
    /// True when no changed ray was added.
    bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    /// Marks `model`'s cells within its dirty reach of this box (TriDexel::mark_dirty_grid); nothing when empty.
    void mark(TriDexel& model) const {
        if (!empty()) model.mark_dirty_grid(lo, hi);
    }
};

/// Subtracts [t0, t1] (grid units) from one ray's sorted, disjoint, non-touching intervals; an
/// interval may shrink, vanish, or split in two. Pieces of zero length are dropped, so the result
/// keeps the invariants. The ends the cut creates get material `cut_material` (the material of the
/// freshly exposed surface); surviving ends keep theirs. Nothing happens when t0 >= t1 or either bound
/// is NaN. Returns true when the ray changed. O(intervals).
/// Source: Peng et al., tri-dexel Boolean subtraction, per ray. The GPU kernel (shaders/dexel_sweep.comp)
/// performs the same steps in the same order.
/// `span` (optional): grown, when the ray changed, to hold the ends the cut removed and made.
bool subtract_interval_changed(std::vector<Interval>& ray, float t0, float t1, std::uint8_t cut_material = 0,
                               ChangedSpan* span = nullptr);

/// Same as subtract_interval_changed, without the result.
void subtract_interval(std::vector<Interval>& ray, float t0, float t1);

/// Adds [t0, t1] (grid units) as material: every interval that overlaps or touches it is merged with it
/// into one interval, so the ray stays sorted, disjoint and non-touching. An end that the added span
/// extends (strictly beyond the old end) gets `material`; the others keep theirs. Nothing happens when
/// t0 >= t1 or either bound is NaN. Returns true when the ray changed. O(intervals).
/// Source: Peng et al., tri-dexel Boolean union, per ray.
/// `span` (optional): grown, when the ray changed, to hold the ends the union removed, moved and made.
bool union_interval_changed(std::vector<Interval>& ray, float t0, float t1, std::uint8_t material,
                            ChangedSpan* span = nullptr);

/// Paints the surface inside [t0, t1]: every interval end (a surface point) with t0 <= depth <= t1 gets
/// `material`. Depths do not change. Nothing happens when t0 > t1 or either bound is NaN. Returns true
/// when a material id changed. O(log intervals + painted ends).
/// `span` (optional): grown to hold the ends whose material changed.
bool paint_interval_changed(std::vector<Interval>& ray, float t0, float t1, std::uint8_t material,
                            ChangedSpan* span = nullptr);

}  // namespace tridex::compute
