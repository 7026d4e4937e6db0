// app/session/view/more_view.hpp - a session's further workpieces (SessionRuntime::more_workpiece) drawn beside its
// first: each one's newest whole mesh, in its materials' colours, through the pose the haptic loop holds it at.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/material_palette.hpp"
#include "core/tri_mesh.hpp"
#include "haptics/haptic_loop.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

class SessionRuntime;

/// The triangles of `mesh` whose first vertex has material `id` (materials: one id per vertex of mesh), with only
/// the vertices they use, in their order. An empty mesh when none; `materials` shorter than the vertices reads as 0.
TriMesh triangles_of_material(const TriMesh& mesh, const std::vector<std::uint8_t>& materials, std::uint8_t id);

/// After a session stopped: appends its further workpieces' final models (MoreWorkpiece::final_mesh), split by
/// material as MoreWorkpiecesView draws them, posed by last.workpiece_poses (their spec's poses when the loop never
/// ticked), to `out`; their meshes go to `keep`, which must outlive the frames that draw them and is cleared first.
/// Returns the placed boxes of the further workpieces' lattices (world m), to frame the picture by.
Aabb append_final_more(SessionRuntime& rt, const haptics::LoopView& last, const MaterialPalette& palette,
                       std::vector<TriMesh>& keep, std::vector<renderer::SceneObject>& out);

/// Draws the further workpieces of a session: each as one object per material it shows (triangles_of_material),
/// in that material's palette colour, lit, placed by the loop view's pose of that workpiece (so a placed workpiece
/// moves with the hand). Keeps the meshes of the newest version it split, so it must outlive the frames that draw
/// them; one thread (the render thread) calls append().
class MoreWorkpiecesView {
public:
    /// Appends the objects of workpieces 1..rt.workpiece_count()-1 to `out`, split again when a workpiece published a
    /// new mesh (SessionRuntime::more_workpiece(k).latest_mesh()), posed by lv.workpiece_poses[k].
    void append(SessionRuntime& rt, const haptics::LoopView& lv, const MaterialPalette& palette,
                std::vector<renderer::SceneObject>& out);

private:
    // Two sets of meshes used in turn: a new version lands at other addresses than the frame before drew, so the
    // renderer (which uploads an object again when its mesh's address or size changes) never keeps an old one.
    struct Piece {
        std::uint64_t version = 0;                                  // the mesh version split into by_material[current]
        std::array<std::array<TriMesh, kPaletteSize>, 2> by_material;  // its triangles by material
        int current = 0;
    };
    std::vector<Piece> pieces_;
};

}  // namespace tridex::app
