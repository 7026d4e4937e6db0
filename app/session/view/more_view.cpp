// app/session/view/more_view.cpp - drawing a session's further workpieces.
#include "app/session/view/more_view.hpp"

#include <limits>

#include "app/session/runtime/session_runtime.hpp"

namespace tridex::app {

TriMesh triangles_of_material(const TriMesh& mesh, const std::vector<std::uint8_t>& materials, std::uint8_t id) {
    constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
    TriMesh out;
    std::vector<std::uint32_t> index(mesh.positions.size(), kUnused);
    for (const std::array<std::uint32_t, 3>& t : mesh.triangles) {
        const std::uint8_t m = t[0] < materials.size() ? materials[t[0]] : 0;
        if (m != id) continue;
        std::array<std::uint32_t, 3> u{};
        for (int c = 0; c < 3; ++c) {
            std::uint32_t& i = index[t[c]];
            if (i == kUnused) {
                i = static_cast<std::uint32_t>(out.positions.size());
                out.positions.push_back(mesh.positions[t[c]]);
            }
            u[c] = i;
        }
        out.triangles.push_back(u);
    }
    return out;
}

namespace {

// One object per material of `by_material` (palette colours, lit), placed by `pose`.
void add_by_material(const TriMesh* by_material, const Pose& pose, const MaterialPalette& palette,
                     std::vector<renderer::SceneObject>& out) {
    for (int id = 0; id < kPaletteSize; ++id) {
        const TriMesh& m = by_material[id];
        if (m.triangles.empty()) continue;
        renderer::SceneObject o;
        o.mesh = &m;
        const std::array<float, 3>& c = palette[id].rgb;
        o.colour = glm::vec4(c[0], c[1], c[2], 1.0f);
        o.world_from_model = glm::mat4(pose.matrix());
        out.push_back(o);
    }
}

}  // namespace

Aabb append_final_more(SessionRuntime& rt, const haptics::LoopView& last, const MaterialPalette& palette,
                       std::vector<TriMesh>& keep, std::vector<renderer::SceneObject>& out) {
    Aabb box;
    keep.clear();
    keep.reserve(rt.workpiece_count() * kPaletteSize);  // no reallocation: `out` points into it
    for (std::size_t k = 1; k < rt.workpiece_count(); ++k) {
        MoreWorkpiece& m = rt.more_workpiece(k);
        std::vector<std::uint8_t> materials;
        const TriMesh mesh = m.final_mesh(materials);
        const std::size_t first = keep.size();
        for (int id = 0; id < kPaletteSize; ++id)
            keep.push_back(triangles_of_material(mesh, materials, static_cast<std::uint8_t>(id)));
        const Pose pose = last.tick > 0 && k < last.workpiece_count ? last.workpiece_poses[k] : m.pose();
        add_by_material(&keep[first], pose, palette, out);
        const Aabb placed_box = placed(m.workpiece().model.lattice.bounds(), pose);
        box.add(placed_box.lo);
        box.add(placed_box.hi);
    }
    return box;
}

void MoreWorkpiecesView::append(SessionRuntime& rt, const haptics::LoopView& lv, const MaterialPalette& palette,
                                std::vector<renderer::SceneObject>& out) {
    const std::size_t n = rt.workpiece_count();
    if (pieces_.size() < n) pieces_.resize(n);
    for (std::size_t k = 1; k < n; ++k) {
        const MeshFrame& f = rt.more_workpiece(k).latest_mesh();
        Piece& p = pieces_[k];
        if (f.version != p.version) {
            p.current = 1 - p.current;
            for (int id = 0; id < kPaletteSize; ++id)
                p.by_material[p.current][id] = triangles_of_material(f.mesh, f.materials, static_cast<std::uint8_t>(id));
            p.version = f.version;
        }
        const Pose pose = k < lv.workpiece_count ? lv.workpiece_poses[k] : rt.more_workpiece(k).pose();
        add_by_material(p.by_material[p.current].data(), pose, palette, out);
    }
}

}  // namespace tridex::app
