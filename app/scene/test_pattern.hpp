// app/scene/test_pattern.hpp - the wall's test pattern: the screen's edges and grid, the corners' names, one label
// per eye and two cubes in depth, for checking a display config's corners, the eye order and the tracker's origin.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "core/tri_mesh.hpp"
#include "renderer/camera/off_axis.hpp"

namespace tridex::app {

/// One piece of the test pattern: a mesh in world m (the display config's frame), its colour (linear RGBA) and the
/// eyes that see it (bit 0 left, bit 1 right), as renderer::SceneObject takes them.
struct PatternPiece {
    TriMesh mesh;
    glm::vec4 colour{1.0f};
    std::uint32_t eyes = 0b11;
    bool lit = false;  ///< flat colour (the marks and text); the cubes are lit, to look solid
};

/// The test pattern for `screen` (its corners as the display config gives them, m):
/// - a border just inside the screen's edges and a grid of eighths of its height, on the screen plane (zero
///   parallax: sharp with or without glasses; the border must meet the physical edges when the corners are right);
/// - "LOWER LEFT", "LOWER RIGHT", "UPPER LEFT" beside the corners the config measured, and "UPPER RIGHT" (the upper
///   two an eighth of the height down, clear of the overlay);
/// - "LEFT EYE" in the left half, drawn for the left eye only, and "RIGHT EYE" in the right half for the right eye
///   only: with one eye closed, the open eye must read its own name (else swap the eyes: Tab, or swap_eyes);
/// - a green cube a fifth of the screen's height in front of its centre and a blue one as far behind: the green one
///   must look nearer (with the eyes swapped, depth is inverted).
/// Text and marks stand 2 mm in front of the grid so they never fight it for depth. Every face is two-sided.
/// Throws tridex::Error for a screen whose corners are not finite or have no area.
std::vector<PatternPiece> wall_test_pattern(const renderer::Screen& screen);

}  // namespace tridex::app
