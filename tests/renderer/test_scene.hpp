// tests/renderer/test_scene.hpp - the small scene the renderer tests draw (cube + ball + workspace box).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "core/aabb.hpp"
#include "core/pose.hpp"
#include "core/tri_mesh.hpp"
#include "renderer/camera/off_axis.hpp"
#include "renderer/scene/primitive_meshes.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::renderer::test {

/// `mesh` with every triangle given its own three vertices, so vertex normals are face normals.
inline TriMesh flat_shaded(const TriMesh& mesh) {
    TriMesh out;
    for (const auto& t : mesh.triangles) {
        const auto base = static_cast<std::uint32_t>(out.positions.size());
        for (int k = 0; k < 3; ++k) out.positions.push_back(mesh.positions[t[k]]);
        out.triangles.push_back({base, base + 1, base + 2});
    }
    return out;
}

/// A 0.4 m x 0.3 m desktop-sized screen centred at the origin in z = 0 (facing +z).
inline Screen small_screen() { return Screen{Vec3(-0.2, -0.15, 0.0), Vec3(0.2, -0.15, 0.0), Vec3(-0.2, 0.15, 0.0)}; }

/// Head 0.5 m in front of the screen, 0.1 m right of and 0.12 m above its centre.
inline Pose test_head() { return Pose{Vec3(0.1, 0.12, 0.5), Quat(1.0, 0.0, 0.0, 0.0)}; }

/// A 0.1 m cube centred on the screen plane, turned 30 degrees about y and then 20 degrees about x.
inline TriMesh test_cube() {
    Aabb box;
    box.add(Vec3(-0.05));
    box.add(Vec3(0.05));
    TriMesh m = flat_shaded(box_mesh(box));
    const double deg = std::acos(-1.0) / 180.0;
    const Quat turn = glm::angleAxis(20.0 * deg, Vec3(1.0, 0.0, 0.0)) * glm::angleAxis(30.0 * deg, Vec3(0.0, 1.0, 0.0));
    for (Vec3& p : m.positions) p = turn * p;
    return m;
}

/// The scene: `cube` as the workpiece, a 3 cm ball tool in front, the workspace box around both.
inline SceneView test_scene(const TriMesh& cube) {
    SceneView s;
    s.workpiece = &cube;
    s.tool_centre_m = Vec3(0.075, 0.045, 0.07);
    s.tool_radius_m = 0.025;
    s.show_workspace = true;
    s.workspace_m.add(Vec3(-0.11, -0.08, -0.08));
    s.workspace_m.add(Vec3(0.11, 0.08, 0.1));
    return s;
}

/// Colour the fragment shader (shaders/stereo_mesh.frag) gives a lit surface with normal +z at world point p seen
/// from `eye`, as UNORM8: the key light from above (towards (0.25, 1, 0.6), normalised), the fill light from the
/// eye and the specular highlight, with the ambient occlusion off (SceneView::occlusion_strength = 0).
inline std::array<int, 3> lit_colour(const glm::vec4& base, const Vec3& p, const Vec3& eye) {
    const Vec3 l = Vec3(glm::normalize(glm::vec3(0.25f, 1.0f, 0.6f)));
    const Vec3 n(0.0, 0.0, 1.0), v = glm::normalize(eye - p), h = glm::normalize(l + v);
    const double diffuse = std::max(glm::dot(n, l), 0.0), fill = std::max(glm::dot(n, v), 0.0);
    const double specular = diffuse > 0.0 ? std::pow(std::max(glm::dot(n, h), 0.0), 48.0) : 0.0;
    std::array<int, 3> out{};
    for (int c = 0; c < 3; ++c)
        out[c] = static_cast<int>(
            std::lround(std::min(base[c] * (0.2 + 0.6 * diffuse + 0.2 * fill) + 0.2 * specular, 1.0) * 255.0));
    return out;
}

}  // namespace tridex::renderer::test
