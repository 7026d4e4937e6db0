// bench/accuracy/bench_accuracy_metrics.cpp - point-to-mesh distances and the error summary.
#include "bench/accuracy/bench_accuracy_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

namespace tridex::bench::accuracy {

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return glm::length(p - a);
    const Vec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return glm::length(p - b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return glm::length(p - (a + (d1 / (d1 - d3)) * ab));
    const Vec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return glm::length(p - c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return glm::length(p - (a + (d2 / (d2 - d6)) * ac));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
        return glm::length(p - (b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)));
    const double denom = 1.0 / (va + vb + vc);
    return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

MeshDistance::MeshDistance(const TriMesh& mesh, double cell_m) : mesh_(mesh), cell_(cell_m) {
    const Aabb b = mesh.bounds();
    if (b.empty()) {
        start_.assign(2, 0);
        return;
    }
    lo_ = b.lo;
    for (int a = 0; a < 3; ++a) dims_[a] = std::max(1, static_cast<int>(std::ceil((b.hi[a] - b.lo[a]) / cell_)) + 1);
    const std::size_t cells = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
    auto cell_range = [&](std::size_t t, int lo[3], int hi[3]) {
        Aabb tb;
        for (const std::uint32_t v : mesh.triangles[t]) tb.add(mesh.positions[v]);
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::clamp(static_cast<int>((tb.lo[a] - lo_[a]) / cell_), 0, dims_[a] - 1);
            hi[a] = std::clamp(static_cast<int>((tb.hi[a] - lo_[a]) / cell_), 0, dims_[a] - 1);
        }
    };
    std::vector<std::uint32_t> count(cells + 1, 0);
    int lo[3], hi[3];
    for (int pass = 0; pass < 2; ++pass) {
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            cell_range(t, lo, hi);
            for (int z = lo[2]; z <= hi[2]; ++z)
                for (int y = lo[1]; y <= hi[1]; ++y)
                    for (int x = lo[0]; x <= hi[0]; ++x) {
                        const std::size_t c = x + static_cast<std::size_t>(dims_[0]) * (y + static_cast<std::size_t>(dims_[1]) * z);
                        if (pass == 0) ++count[c + 1];
                        else tris_[count[c]++] = static_cast<std::uint32_t>(t);
                    }
        }
        if (pass == 0) {
            for (std::size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
            start_ = count;
            tris_.resize(count[cells]);
        }
    }
}

double MeshDistance::distance(const Vec3& p) const {
    double best = std::numeric_limits<double>::infinity();
    if (tris_.empty()) return best;
    int c[3];
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor((p[a] - lo_[a]) / cell_)), 0, dims_[a] - 1);
    const int max_r = std::max(dims_[0], std::max(dims_[1], dims_[2]));
    for (int r = 0; r <= max_r; ++r) {
        for (int z = c[2] - r; z <= c[2] + r; ++z) {
            if (z < 0 || z >= dims_[2]) continue;
            for (int y = c[1] - r; y <= c[1] + r; ++y) {
                if (y < 0 || y >= dims_[1]) continue;
                const bool shell_zy = std::abs(z - c[2]) == r || std::abs(y - c[1]) == r;
                for (int x = c[0] - r; x <= c[0] + r; x += (shell_zy || r == 0) ? 1 : 2 * r) {
                    if (x < 0 || x >= dims_[0]) continue;
                    const std::size_t cell = x + static_cast<std::size_t>(dims_[0]) * (y + static_cast<std::size_t>(dims_[1]) * z);
                    for (std::uint32_t i = start_[cell]; i < start_[cell + 1]; ++i) {
                        const auto& t = mesh_.triangles[tris_[i]];
                        best = std::min(best, point_triangle_distance(p, mesh_.positions[t[0]], mesh_.positions[t[1]], mesh_.positions[t[2]]));
                    }
                }
            }
        }
        // Every cell not yet visited is at least r cells (beyond p's own cell) away.
        if (best <= r * cell_) break;
    }
    return best;
}

SurfaceErrors surface_errors(const TriMesh& mesh, const ExactSolid& exact, const std::vector<Vec3>& samples,
                             double grid_cell_m, int threads) {
    SurfaceErrors e;
    const MeshDistance md(mesh, grid_cell_m);
    threads = std::max(1, threads);
    std::vector<double> vsum(threads, 0.0), vmax(threads, -1.0), ssum(threads, 0.0), smax(threads, -1.0);
    std::vector<Vec3> vat(threads, Vec3(0.0)), sat(threads, Vec3(0.0));
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (std::size_t i = t; i < mesh.positions.size(); i += threads) {
                const double d = std::abs(exact.sdf(mesh.positions[i]));
                vsum[t] += d;
                if (d > vmax[t]) {
                    vmax[t] = d;
                    vat[t] = mesh.positions[i];
                }
            }
            for (std::size_t i = t; i < samples.size(); i += threads) {
                const double d = md.distance(samples[i]);
                ssum[t] += d;
                if (d > smax[t]) {
                    smax[t] = d;
                    sat[t] = samples[i];
                }
            }
        });
    for (auto& th : pool) th.join();
    e.vertices = mesh.positions.size();
    e.samples = samples.size();
    for (int t = 0; t < threads; ++t) {
        e.mean_vertex_m += vsum[t];
        e.mean_surface_m += ssum[t];
        if (vmax[t] > e.max_vertex_m) {
            e.max_vertex_m = vmax[t];
            e.worst_vertex = vat[t];
        }
        if (smax[t] > e.max_surface_m) {
            e.max_surface_m = smax[t];
            e.worst_sample = sat[t];
        }
    }
    if (e.vertices) e.mean_vertex_m /= static_cast<double>(e.vertices);
    if (e.samples) e.mean_surface_m /= static_cast<double>(e.samples);
    e.hausdorff_m = std::max(e.max_vertex_m, e.max_surface_m);
    return e;
}

}  // namespace tridex::bench::accuracy
