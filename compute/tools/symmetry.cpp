// compute/tools/symmetry.cpp - mirror and radial copies of tool poses and sweeps.
#include "compute/tools/symmetry.hpp"

#include <cmath>
#include <numbers>
#include <utility>

#include "core/error.hpp"

namespace tridex::compute {

std::vector<SymmetryTransform> symmetry_transforms(const Symmetry& s) {
    if (!valid_symmetry(s)) throw Error("symmetry: not a valid symmetry (" + to_string(s) + ")");
    std::vector<SymmetryTransform> out;
    if (s.radial_copies != 0) {
        const int a = s.radial_axis, u = (a + 1) % 3, v = (a + 2) % 3;
        for (int k = 0; k < s.radial_copies; ++k) {
            SymmetryTransform t;
            if (k > 0) {
                const double phi = 2.0 * std::numbers::pi * k / s.radial_copies;
                const double c = std::cos(phi), sn = std::sin(phi);
                // glm matrices are column-major: m[col][row]. A right-handed turn about axis a takes u toward v.
                t.linear[u][u] = c;
                t.linear[u][v] = sn;
                t.linear[v][u] = -sn;
                t.linear[v][v] = c;
            }
            out.push_back(t);
        }
        return out;
    }
    for (unsigned subset = 0; subset < 8; ++subset) {
        if ((subset & ~static_cast<unsigned>(s.mirrors)) != 0) continue;
        SymmetryTransform t;
        int flips = 0;
        for (int a = 0; a < 3; ++a)
            if (subset & (1u << a)) {
                t.linear[a][a] = -1.0;
                ++flips;
            }
        t.mirrored = flips % 2 == 1;
        out.push_back(t);
    }
    return out;
}

Vec3 symmetry_centre(const Lattice& lattice) {
    return lattice.origin_m + 0.5 * lattice.cell_m * Vec3(lattice.cells[0], lattice.cells[1], lattice.cells[2]);
}

glm::dmat3 tool_frame_reflection() {
    glm::dmat3 m(1.0);
    m[0][0] = -1.0;
    return m;
}

namespace {

Vec3 map_point(const SymmetryTransform& t, const Vec3& centre, const Vec3& p) { return centre + t.linear * (p - centre); }

glm::dmat3 copy_rotation(const SymmetryTransform& t, const glm::dmat3& r) {
    return t.mirrored ? t.linear * r * tool_frame_reflection() : t.linear * r;
}

}  // namespace

Pose symmetric_pose(const SymmetryTransform& t, const Vec3& centre_m, const Pose& pose) {
    Pose p;
    p.position = map_point(t, centre_m, pose.position);
    p.orientation = glm::normalize(glm::quat_cast(copy_rotation(t, glm::mat3_cast(pose.orientation))));
    return p;
}

std::shared_ptr<const MeshTool> mirrored_mesh_tool(const MeshTool& tool) {
    TriMesh m = tool.mesh();
    for (Vec3& p : m.positions) p.x = -p.x;
    return MeshTool::create(std::move(m), tool.rays_per_cell(), "(mirror image)");
}

void symmetric_sweeps(const Sweep& sweep, const Symmetry& s, const Vec3& centre_m,
                      const std::shared_ptr<const MeshTool>& mirrored_mesh, std::vector<Sweep>& out) {
    const std::vector<SymmetryTransform> ts = symmetry_transforms(s);
    out.push_back(sweep);  // the identity: the sweep itself, bit for bit
    for (std::size_t k = 1; k < ts.size(); ++k) {
        const SymmetryTransform& t = ts[k];
        Sweep c = sweep;
        c.path_m = Segment{map_point(t, centre_m, sweep.path_m.a), map_point(t, centre_m, sweep.path_m.b)};
        c.axis = t.linear * sweep.axis;
        if (sweep.tool.kind == ToolKind::kMesh && sweep.op != ToolOp::kNone) {
            c.orientation = glm::normalize(glm::quat_cast(copy_rotation(t, mesh_sweep_rotation(sweep))));
            if (t.mirrored) {
                if (!mirrored_mesh) throw Error("symmetry: a mirrored mesh tool needs the tool's mirror image");
                c.tool.mesh = mirrored_mesh;
            }
        }
        out.push_back(std::move(c));
    }
}

}  // namespace tridex::compute
