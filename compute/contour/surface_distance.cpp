// compute/contour/surface_distance.cpp - point-to-triangle distance, a bucket grid of triangles, surface samples.
#include "compute/contour/surface_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/aabb.hpp"

namespace tridex::compute {

namespace {

// Closest point to p on the segments of a degenerate (collinear or point-like) triangle.
Vec3 closest_on_segments(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    Vec3 best = a;
    double best_d = glm::dot(p - a, p - a);
    const Vec3 ends[3][2] = {{a, b}, {b, c}, {c, a}};
    for (const auto& e : ends) {
        const Vec3 d = e[1] - e[0];
        const double len2 = glm::dot(d, d);
        const double t = len2 > 0.0 ? std::clamp(glm::dot(p - e[0], d) / len2, 0.0, 1.0) : 0.0;
        const Vec3 q = e[0] + t * d;
        const double dq = glm::dot(p - q, p - q);
        if (dq < best_d) {
            best_d = dq;
            best = q;
        }
    }
    return best;
}

}  // namespace

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    // Degenerate triangles first: the region tests below divide by quantities that vanish with the area.
    const Vec3 n = glm::cross(ab, ac);
    if (!(glm::dot(n, n) > 1e-24 * glm::dot(ab, ab) * glm::dot(ac, ac))) return closest_on_segments(p, a, b, c);
    // Voronoi regions of the corners, then of the edges, else the face (Ericson 5.1.5).
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    const Vec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
    const Vec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    const double sum = va + vb + vc;
    return a + (vb / sum) * ab + (vc / sum) * ac;
}

TriangleGrid::TriangleGrid(const TriMesh& mesh, double bucket) {
    tris_.reserve(mesh.triangles.size());
    Aabb box;
    for (const auto& t : mesh.triangles) {
        tris_.push_back({mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]});
        const auto& q = tris_.back();
        boxes_.push_back({glm::min(glm::min(q[0], q[1]), q[2]), glm::max(glm::max(q[0], q[1]), q[2])});
        for (const Vec3& p : q) box.add(p);
    }
    if (tris_.empty()) return;
    const Vec3 size = box.size();
    const double longest = std::max({size.x, size.y, size.z});
    if (!(bucket > 0.0) || !std::isfinite(bucket)) bucket = longest / 16.0;
    if (!(bucket > 0.0)) bucket = 1.0;  // every triangle in one point
    // At most 64 buckets per side: a coarser grid only costs more triangles per bucket.
    bucket = std::max(bucket, longest / 64.0);
    bucket_ = bucket;
    lo_ = box.lo;
    for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, static_cast<int>(std::ceil(size[a] / bucket_)) + (size[a] > 0.0 ? 0 : 1));
    const auto cell_of = [&](const Vec3& p, int a) {
        return std::clamp(static_cast<int>(std::floor((p[a] - lo_[a]) / bucket_)), 0, dims_[a] - 1);
    };
    const std::size_t buckets = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
    std::vector<std::uint32_t> count(buckets + 1, 0);
    const auto for_each_bucket = [&](const std::array<Vec3, 3>& t, auto&& f) {
        std::array<int, 3> lo{}, hi{};
        for (int a = 0; a < 3; ++a) {
            lo[a] = cell_of(glm::min(glm::min(t[0], t[1]), t[2]), a);
            hi[a] = cell_of(glm::max(glm::max(t[0], t[1]), t[2]), a);
        }
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x)
                    f((static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0] + x);
    };
    for (const auto& t : tris_) for_each_bucket(t, [&](std::size_t b) { ++count[b + 1]; });
    for (std::size_t b = 0; b < buckets; ++b) count[b + 1] += count[b];
    start_ = count;
    items_.resize(count[buckets]);
    for (std::uint32_t i = 0; i < tris_.size(); ++i) for_each_bucket(tris_[i], [&](std::size_t b) { items_[count[b]++] = i; });
    seen_.assign(tris_.size(), 0);
}

double TriangleGrid::distance(const Vec3& p, double enough) {
    if (tris_.empty()) return std::numeric_limits<double>::infinity();
    if (++stamp_ == 0) {  // wrapped: forget every visit
        std::fill(seen_.begin(), seen_.end(), 0u);
        stamp_ = 1;
    }
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a)
        c[a] = std::clamp(static_cast<int>(std::floor((p[a] - lo_[a]) / bucket_)), 0, dims_[a] - 1);
    // Start from the last query's nearest triangle: its distance bounds the search (the box test below).
    double best2 = std::numeric_limits<double>::infinity();
    std::uint32_t best_i = hint_ < tris_.size() ? hint_ : 0;
    {
        const auto& t = tris_[best_i];
        const Vec3 q = closest_point_on_triangle(p, t[0], t[1], t[2]);
        best2 = glm::dot(p - q, p - q);
    }
    const double enough2 = enough > 0.0 ? enough * enough : -1.0;
    if (best2 <= enough2) return std::sqrt(best2);
    // How far p lies inside its bucket from the bucket's nearest face (0 when p is outside the grid there).
    double inside = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
        const double lo = lo_[a] + c[a] * bucket_;
        inside = std::min(inside, std::max(0.0, std::min(p[a] - lo, lo + bucket_ - p[a])));
    }
    const int max_ring = std::max({dims_[0], dims_[1], dims_[2]});
    for (int r = 0; r <= max_ring; ++r) {
        // Buckets at Chebyshev distance exactly r from c.
        for (int z = c[2] - r; z <= c[2] + r; ++z) {
            if (z < 0 || z >= dims_[2]) continue;
            for (int y = c[1] - r; y <= c[1] + r; ++y) {
                if (y < 0 || y >= dims_[1]) continue;
                const bool face = std::abs(z - c[2]) == r || std::abs(y - c[1]) == r;
                for (int x = c[0] - r; x <= c[0] + r; x += (face || r == 0) ? 1 : 2 * r) {
                    if (x < 0 || x >= dims_[0]) continue;
                    const std::size_t b = (static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0] + x;
                    for (std::uint32_t k = start_[b]; k < start_[b + 1]; ++k) {
                        const std::uint32_t i = items_[k];
                        if (seen_[i] == stamp_) continue;
                        seen_[i] = stamp_;
                        // The triangle's box is a lower bound: skip it when that is no nearer than the best.
                        const Vec3 gap = glm::max(glm::max(boxes_[i][0] - p, p - boxes_[i][1]), Vec3(0.0));
                        if (glm::dot(gap, gap) >= best2) continue;
                        const auto& t = tris_[i];
                        const Vec3 q = closest_point_on_triangle(p, t[0], t[1], t[2]);
                        const double d2 = glm::dot(p - q, p - q);
                        if (d2 < best2) {
                            best2 = d2;
                            best_i = i;
                            if (best2 <= enough2) {
                                hint_ = best_i;
                                return std::sqrt(best2);
                            }
                        }
                    }
                }
            }
        }
        // Triangles not seen yet lie only in buckets of ring r + 1 or beyond: at least r buckets plus p's depth
        // inside its own bucket away.
        const double reach = static_cast<double>(r) * bucket_ + inside;
        if (best2 <= reach * reach) break;
    }
    hint_ = best_i;
    return std::sqrt(best2);
}

double sampled_distance(std::span<const Vec3> points, TriangleGrid& grid, std::size_t step, std::size_t& k,
                        double worst) {
    if (points.empty()) return worst;
    step = std::max<std::size_t>(step, 1);
    std::array<std::size_t, 6> extreme{};
    for (std::size_t i = 0; i < points.size(); ++i) {
        for (int a = 0; a < 3; ++a) {
            if (points[i][a] < points[extreme[2 * a]][a]) extreme[2 * a] = i;
            if (points[i][a] > points[extreme[2 * a + 1]][a]) extreme[2 * a + 1] = i;
        }
        if (k++ % step == 0) worst = std::max(worst, grid.distance(points[i], worst));
    }
    for (const std::size_t i : extreme) worst = std::max(worst, grid.distance(points[i], worst));
    return worst;
}

double max_distance(std::span<const Vec3> points, TriangleGrid& surface) {
    double d = 0.0;
    for (const Vec3& p : points) d = std::max(d, surface.distance(p, d));
    return d;
}

std::vector<Vec3> surface_samples(const TriMesh& mesh, double spacing) {
    std::vector<Vec3> out;
    std::vector<std::uint8_t> used(mesh.positions.size(), 0);
    for (const auto& t : mesh.triangles)
        for (std::uint32_t v : t)
            if (!used[v]) {
                used[v] = 1;
                out.push_back(mesh.positions[v]);
            }
    for (const auto& t : mesh.triangles) {
        const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
        const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
        const int n = std::clamp(static_cast<int>(std::ceil(longest / spacing)), 1, 4096);
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                if ((i == 0 && j == 0) || i == n || j == n) continue;  // the corners: added once above
                const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
                out.push_back(a + u * (b - a) + v * (c - a));
            }
    }
    return out;
}

}  // namespace tridex::compute
