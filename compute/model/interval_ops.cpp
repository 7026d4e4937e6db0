// compute/model/interval_ops.cpp - subtract, union and paint on one ray's interval list.
#include "compute/model/interval_ops.hpp"

#include <algorithm>
#include <iterator>

namespace tridex::compute {

bool subtract_interval_changed(std::vector<Interval>& ray, float t0, float t1, std::uint8_t cut_material,
                               ChangedSpan* span) {
    if (!(t0 < t1)) return false;
    // First interval whose exit is beyond t0, and first one (from there) whose entry is at or past t1.
    auto first = std::upper_bound(ray.begin(), ray.end(), t0, [](float t, const Interval& iv) { return t < iv.exit; });
    auto last = std::lower_bound(first, ray.end(), t1, [](const Interval& iv, float t) { return iv.enter < t; });
    if (first == last) return false;  // no interval overlaps (t0, t1)
    // Pieces that survive on either side of the cut.
    const Interval head{first->enter, t0, first->enter_material, cut_material};
    const Interval tail{t1, std::prev(last)->exit, cut_material, std::prev(last)->exit_material};
    const bool keep_head = head.enter < head.exit, keep_tail = tail.enter < tail.exit;
    // Ends removed: those of the overlapped intervals inside (t0, t1); made: t0 and t1 where pieces survive.
    if (span != nullptr) span->add(keep_head ? t0 : first->enter, keep_tail ? t1 : std::prev(last)->exit);
    const auto at = ray.erase(first, last) - ray.begin();
    if (keep_tail) ray.insert(ray.begin() + at, tail);
    if (keep_head) ray.insert(ray.begin() + at, head);
    return true;
}

void subtract_interval(std::vector<Interval>& ray, float t0, float t1) { subtract_interval_changed(ray, t0, t1); }

bool union_interval_changed(std::vector<Interval>& ray, float t0, float t1, std::uint8_t material, ChangedSpan* span) {
    if (!(t0 < t1)) return false;
    // Intervals overlapping or touching [t0, t1]: from the first whose exit >= t0 to before the first
    // whose entry > t1.
    auto first = std::lower_bound(ray.begin(), ray.end(), t0, [](const Interval& iv, float t) { return iv.exit < t; });
    auto last = std::upper_bound(first, ray.end(), t1, [](float t, const Interval& iv) { return t < iv.enter; });
    if (first == last) {
        ray.insert(first, Interval{t0, t1, material, material});
        if (span != nullptr) span->add(t0, t1);
        return true;
    }
    const Interval& lo = *first;
    const Interval& hi = *std::prev(last);
    if (std::next(first) == last && lo.enter <= t0 && t1 <= lo.exit) return false;  // already solid
    // Ends kept: lo's entry unless t0 extends it, hi's exit unless t1 does; every end between them is removed.
    if (span != nullptr) span->add(t0 < lo.enter ? t0 : lo.exit, t1 > hi.exit ? t1 : hi.enter);
    Interval merged = lo;
    if (t0 < lo.enter) {
        merged.enter = t0;
        merged.enter_material = material;
    }
    merged.exit = hi.exit;
    merged.exit_material = hi.exit_material;
    if (t1 > hi.exit) {
        merged.exit = t1;
        merged.exit_material = material;
    }
    const auto at = ray.erase(first, last) - ray.begin();
    ray.insert(ray.begin() + at, merged);
    return true;
}

ChangedSpan changed_span(const std::vector<Interval>& before, const std::vector<Interval>& after) {
    // End e of a ray: interval e / 2, its entry when e is even; both rays alternate entry, exit from the start and
    // from the end, so equal positions from either side are the same kind of end.
    const auto depth = [](const std::vector<Interval>& r, std::size_t e) {
        return e % 2 == 0 ? r[e / 2].enter : r[e / 2].exit;
    };
    const auto same = [&](std::size_t ea, std::size_t eb) {
        const Interval &x = before[ea / 2], &y = after[eb / 2];
        return ea % 2 == 0 ? x.enter == y.enter && x.enter_material == y.enter_material
                           : x.exit == y.exit && x.exit_material == y.exit_material;
    };
    const std::size_t na = 2 * before.size(), nb = 2 * after.size(), n = std::min(na, nb);
    std::size_t lead = 0;
    while (lead < n && same(lead, lead)) ++lead;
    std::size_t trail = 0;
    while (trail < n - lead && same(na - 1 - trail, nb - 1 - trail)) ++trail;
    ChangedSpan span;
    for (std::size_t e = lead; e + trail < na; ++e) span.add(depth(before, e), depth(before, e));
    for (std::size_t e = lead; e + trail < nb; ++e) span.add(depth(after, e), depth(after, e));
    return span;
}

bool paint_interval_changed(std::vector<Interval>& ray, float t0, float t1, std::uint8_t material, ChangedSpan* span) {
    if (!(t0 <= t1)) return false;
    bool changed = false;
    auto it = std::lower_bound(ray.begin(), ray.end(), t0, [](const Interval& iv, float t) { return iv.exit < t; });
    for (; it != ray.end() && it->enter <= t1; ++it) {
        if (t0 <= it->enter && it->enter_material != material) {
            it->enter_material = material;
            changed = true;
            if (span != nullptr) span->add(it->enter, it->enter);
        }
        if (it->exit <= t1 && it->exit_material != material) {
            it->exit_material = material;
            changed = true;
            if (span != nullptr) span->add(it->exit, it->exit);
        }
    }
    return changed;
}

}  // namespace tridex::compute
