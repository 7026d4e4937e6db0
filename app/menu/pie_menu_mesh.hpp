// app/menu/pie_menu_mesh.hpp - the open pie menu as world-space meshes at the hand, for both eyes' off-axis frusta.
#pragma once

#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "app/menu/pie_menu.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::app {

/// One piece of the drawn menu: a mesh in the ring's frame of reference (world m) and its flat colour (linear RGBA).
struct MenuPiece {
    TriMesh mesh;
    glm::vec4 colour{1.0f};
};

/// The ring's meshes, in the ring's plane through the hand (so both eyes see it at the hand's depth, never at the
/// screen's): [0] the slices and the labels' backing (dark), [1] the lit slice (orange), [2] the labels, glyphs and
/// the `status` lines below the ring (white). Slice k spans its 360/n degrees less a small gap, from 1.4 dead radii
/// to the ring's radius; its glyph sits inside it and its label just outside the ring, anchored away from the centre.
/// Marks stand 1 mm and text 2 mm towards the head, so they never fight the slices for depth. Every face is two-sided.
/// Returns no pieces when the ring has no slices.
std::vector<MenuPiece> pie_menu_pieces(const RingView& ring, const std::string& status);

}  // namespace tridex::app
