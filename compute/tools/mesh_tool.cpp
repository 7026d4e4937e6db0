// compute/tools/mesh_tool.cpp - checking a tool mesh, turning it onto an axis, scan-converting it into tool dexels.
#include "compute/tools/mesh_tool.hpp"

#include <algorithm>
#include <cmath>

#include "compute/mesh/mesh_io.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tridexel.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

Vec3 unit_axis(const Vec3& axis) {
    if (!is_finite(axis) || !(glm::length(axis) > 0.0)) throw Error("mesh tool: tool axis must be a finite, non-zero vector");
    return glm::normalize(axis);
}

/// Builds set `a` of a ToolDexels from the tool's tri-dexel model on its own lattice (cell h = cell/k),
/// whose node `ref` is the reference point.
ToolDexelSet flatten(const RaySet& set, const std::array<int, 3>& ref, int k) {
    const int a = set.axis, ua = (a + 1) % 3, va = (a + 2) % 3;
    ToolDexelSet out;
    out.nu = set.nu;
    out.nv = set.nv;
    out.ref_u = ref[ua];
    out.ref_v = ref[va];
    out.first.reserve(set.rays.size() + 1);
    out.first.push_back(0);
    for (const std::vector<Interval>& ray : set.rays) {
        for (const Interval& iv : ray) {
            out.depth.push_back(static_cast<float>((static_cast<double>(iv.enter) - ref[a]) / k));
            out.depth.push_back(static_cast<float>((static_cast<double>(iv.exit) - ref[a]) / k));
        }
        out.first.push_back(static_cast<std::uint32_t>(out.depth.size() / 2));
    }
    return out;
}

void check_rotation(const glm::dmat3& R, const std::string& name) {
    for (int c = 0; c < 3; ++c)
        if (!is_finite(R[c])) throw Error("mesh tool " + name + ": tool rotation is not finite");
}

}  // namespace

std::size_t ToolDexels::interval_count() const {
    std::size_t n = 0;
    for (const ToolDexelSet& s : sets) n += s.depth.size() / 2;
    return n;
}

glm::dmat3 tool_rotation(const Vec3& axis) {
    const Vec3 n = unit_axis(axis);
    const double c = n.z;      // dot(+z, n)
    const Vec3 v(-n.y, n.x, 0.0);  // z x n, |v| = sin(angle)
    const double vv = glm::dot(v, v);
    if (vv == 0.0) return c > 0.0 ? glm::dmat3(1.0) : glm::dmat3(Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, -1));  // half turn about +x
    const glm::dmat3 vx(Vec3(0.0, v.z, -v.y), Vec3(-v.z, 0.0, v.x), Vec3(v.y, -v.x, 0.0));  // columns of [v]x
    // Rodrigues: I + [v]x + [v]x^2 (1 - c) / |v|^2 (= 1 / (1 + c), without its cancellation near -z).
    return glm::dmat3(1.0) + vx + (vx * vx) * ((1.0 - c) / vv);
}

glm::dmat3 tool_rotation(const Quat& q) {
    const double len = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (!std::isfinite(len) || !(len > 0.0)) throw Error("mesh tool: tool orientation must be a finite, non-zero quaternion");
    return glm::mat3_cast(q / len);
}

std::shared_ptr<const MeshTool> MeshTool::create(TriMesh tool_m, int k, const std::string& name) {
    const std::string who = "mesh tool " + name + ": ";
    if (k < 1 || k > 16) throw Error(who + "rays per cell k must be in [1, 16], got " + std::to_string(k));
    if (tool_m.triangles.empty()) throw Error(who + "mesh has no triangles");
    for (const Vec3& p : tool_m.positions)
        if (!is_finite(p)) throw Error(who + "a vertex position is not finite");
    for (const auto& t : tool_m.triangles)
        for (const std::uint32_t i : t)
            if (i >= tool_m.positions.size()) throw Error(who + "triangle index " + std::to_string(i) + " out of range");
    const EdgeStats es = edge_stats(tool_m);
    if (es.degenerate_triangles > 0) throw Error(who + "mesh has " + std::to_string(es.degenerate_triangles) + " degenerate triangles (repeated vertex)");
    if (es.boundary_edges > 0) throw Error(who + "mesh is not closed: " + std::to_string(es.boundary_edges) + " boundary edges");
    if (es.nonmanifold_edges > 0) throw Error(who + "mesh is not manifold: " + std::to_string(es.nonmanifold_edges) + " non-manifold edges");
    if (es.misoriented_edges > 0) throw Error(who + "mesh is not consistently oriented: " + std::to_string(es.misoriented_edges) + " misoriented edges");
    const double diag = glm::length(tool_m.bounds().size());
    std::size_t zero_area = 0;
    for (const auto& t : tool_m.triangles) {
        const Vec3& a = tool_m.positions[t[0]];
        const double area2 = glm::length(glm::cross(tool_m.positions[t[1]] - a, tool_m.positions[t[2]] - a));
        if (!(area2 > 1e-14 * diag * diag)) ++zero_area;
    }
    if (zero_area > 0) throw Error(who + "mesh has " + std::to_string(zero_area) + " degenerate (zero-area) triangles");
    const double vol = signed_volume(tool_m);
    if (!(std::fabs(vol) > 0.0) || !std::isfinite(vol)) throw Error(who + "mesh encloses zero volume");
    if (vol < 0.0)
        for (auto& t : tool_m.triangles) std::swap(t[1], t[2]);

    std::shared_ptr<MeshTool> tool(new MeshTool());
    for (const Vec3& p : tool_m.positions) tool->radius_m_ = std::max(tool->radius_m_, glm::length(p));
    tool->mesh_ = std::move(tool_m);
    tool->k_ = k;
    tool->name_ = name;
    return tool;
}

std::shared_ptr<const MeshTool> MeshTool::load(const std::string& path, double scale_m, int k) {
    if (!std::isfinite(scale_m) || !(scale_m > 0.0)) throw Error(path + ": mesh tool scale must be a positive number, got " + std::to_string(scale_m));
    TriMesh m = load_closed_mesh(path);
    for (Vec3& p : m.positions) p *= scale_m;
    return create(std::move(m), k, path);
}

Aabb MeshTool::rotated_bounds(const Vec3& axis) const { return rotated_bounds(tool_rotation(axis)); }

Aabb MeshTool::rotated_bounds(const glm::dmat3& R) const {
    check_rotation(R, name_);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!bounds_.empty() && bounds_rotation_ == R) return bounds_;
    Aabb box;
    for (const Vec3& p : mesh_.positions) box.add(R * p);
    bounds_rotation_ = R;
    bounds_ = box;
    return box;
}

std::shared_ptr<const ToolDexels> MeshTool::dexels(const Vec3& axis, double cell_m) const {
    return dexels(tool_rotation(axis), cell_m);
}

std::shared_ptr<const ToolDexels> MeshTool::dexels(const glm::dmat3& R, double cell_m) const {
    if (!std::isfinite(cell_m) || !(cell_m > 0.0)) throw Error("mesh tool " + name_ + ": cell size must be a positive number of metres");
    check_rotation(R, name_);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto it = cache_.begin(); it != cache_.end(); ++it)
            if ((*it)->rotation == R && (*it)->cell_m == cell_m) {
                std::shared_ptr<const ToolDexels> hit = *it;
                cache_.erase(it);
                cache_.push_back(hit);
                return hit;
            }
    }
    // Build outside the lock (two threads may build the same entry; both results are equal).
    TriMesh turned = mesh_;
    Aabb box;
    for (Vec3& p : turned.positions) {
        p = R * p;
        box.add(p);
    }
    const double h = cell_m / k_;
    Lattice L;
    L.cell_m = h;
    std::array<int, 3> ref{};
    for (int a = 0; a < 3; ++a) {
        const double lo = std::floor(box.lo[a] / h) - 1.0, hi = std::ceil(box.hi[a] / h) + 1.0;
        if (!(hi - lo < 1.0e5)) throw Error("mesh tool " + name_ + ": tool is over 100000 tool rays (" + std::to_string(k_) + " per cell) across");
        L.origin_m[a] = lo * h;
        L.cells[a] = static_cast<int>(hi - lo);
        ref[a] = static_cast<int>(-lo);
    }
    TriDexel model = TriDexel::empty(L, kMaxToolBytes);
    scan_convert(turned, model);
    auto out = std::make_shared<ToolDexels>();
    out->k = k_;
    out->cell_m = cell_m;
    out->axis = R * Vec3(0.0, 0.0, 1.0);
    out->rotation = R;
    out->lo_cells = box.lo / cell_m;
    out->hi_cells = box.hi / cell_m;
    for (int a = 0; a < 3; ++a) out->sets[a] = flatten(model.sets[a], ref, k_);
    std::lock_guard<std::mutex> lock(mutex_);
    cache_.push_back(out);
    if (cache_.size() > kCacheEntries) cache_.erase(cache_.begin());
    return out;
}

}  // namespace tridex::compute
