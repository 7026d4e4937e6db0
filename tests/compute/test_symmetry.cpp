// Symmetry: the names and their refusals, the copies of a pose, and sweeps applied with symmetry on analytic
// stock: the same dexels as the copies applied one by one, and a mirror-symmetric model after a mirrored cut.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "compute/mesh/scan_convert.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "compute/tools/symmetry.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

namespace tridex::compute {
namespace {

// A cube centred in its lattice, its faces between lattice nodes (a face through nodes would be held by the rays on
// one side only: scan conversion's half-open rule, which no mirror keeps).
TriDexel box_model() {
    TriDexel m = TriDexel::empty(Lattice::around(Aabb{Vec3(-0.05), Vec3(0.05)}, 40), std::size_t(1) << 30);
    scan_convert(box_mesh(Aabb{Vec3(-0.0487), Vec3(0.0487)}), m);
    return m;
}

std::string refusal(const std::string& text) {
    try {
        parse_symmetry(text, "--symmetry");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Symmetry, NamesRoundTripAndBadValuesAreRefusedNamingTheOption) {
    for (const char* t : {"off", "x", "y", "z", "xy", "xz", "yz", "xyz", "radial:2:x", "radial:6:y", "radial:32:z"}) {
        const Symmetry s = parse_symmetry(t, "--symmetry");
        EXPECT_TRUE(valid_symmetry(s)) << t;
        EXPECT_EQ(to_string(s), t);
    }
    EXPECT_EQ(parse_symmetry("xyz", "f").copies(), 8);
    EXPECT_EQ(parse_symmetry("xz", "f").copies(), 4);
    EXPECT_EQ(parse_symmetry("radial:7:z", "f").copies(), 7);
    EXPECT_EQ(parse_symmetry("none", "f"), Symmetry{});
    const std::string forms = "; use off, x, y, z, xy, xz, yz, xyz or radial:N:AXIS (N 2..32, AXIS x, y or z)";
    EXPECT_EQ(refusal("w"), "--symmetry: bad symmetry 'w'" + forms);
    EXPECT_EQ(refusal("yx"), "--symmetry: bad symmetry 'yx'" + forms);
    EXPECT_EQ(refusal("xx"), "--symmetry: bad symmetry 'xx'" + forms);
    EXPECT_EQ(refusal(""), "--symmetry: bad symmetry ''" + forms);
    EXPECT_EQ(refusal("radial:1:z"), "--symmetry: bad symmetry 'radial:1:z' (N = 1 is outside 2..32)" + forms);
    EXPECT_EQ(refusal("radial:33:z"), "--symmetry: bad symmetry 'radial:33:z' (N = 33 is outside 2..32)" + forms);
    EXPECT_EQ(refusal("radial:4:w"), "--symmetry: bad symmetry 'radial:4:w' (the axis must be x, y or z)" + forms);
    EXPECT_EQ(refusal("radial:4"), "--symmetry: bad symmetry 'radial:4'" + forms);
    EXPECT_EQ(refusal("radial:-4:z"), "--symmetry: bad symmetry 'radial:-4:z'" + forms);
    EXPECT_FALSE(valid_symmetry(Symmetry{1, 0, 4}));  // mirrors and radial copies together
    EXPECT_FALSE(valid_symmetry(Symmetry{8, 0, 0}));
    EXPECT_FALSE(valid_symmetry(Symmetry{0, 1, 0}));
    EXPECT_EQ(symmetry_from_bits(symmetry_bits(Symmetry{0, 2, 17})), (Symmetry{0, 2, 17}));
}

TEST(Symmetry, TransformsAreTheGroupsElementsIdentityFirst) {
    const auto mirrors = symmetry_transforms(parse_symmetry("xyz", "t"));
    ASSERT_EQ(mirrors.size(), 8u);
    int improper = 0;
    for (const SymmetryTransform& t : mirrors) {
        EXPECT_EQ(glm::determinant(t.linear) < 0.0, t.mirrored);
        improper += t.mirrored ? 1 : 0;
    }
    EXPECT_EQ(improper, 4);
    EXPECT_EQ(mirrors[0].linear, glm::dmat3(1.0));
    const auto radial = symmetry_transforms(parse_symmetry("radial:6:y", "t"));
    ASSERT_EQ(radial.size(), 6u);
    EXPECT_EQ(radial[0].linear, glm::dmat3(1.0));
    const Vec3 p = radial[1].linear * Vec3(0.0, 0.3, 1.0);  // a right-handed turn of 60 degrees about +y
    EXPECT_NEAR(p.x, std::sin(std::numbers::pi / 3.0), 1e-15);
    EXPECT_NEAR(p.z, std::cos(std::numbers::pi / 3.0), 1e-15);
    EXPECT_EQ(p.y, 0.3);
    // A mirrored pose is a proper rotation that puts the tool axis where the mirror puts it.
    const Pose tool{Vec3(0.01, 0.02, 0.03), glm::normalize(Quat(0.9, 0.1, -0.3, 0.2))};
    const Pose m = symmetric_pose(mirrors[1], Vec3(0.0), tool);
    EXPECT_EQ(m.position, Vec3(-0.01, 0.02, 0.03));
    const Vec3 axis = tool.orientation * tool_axis_local(), maxis = m.orientation * tool_axis_local();
    EXPECT_NEAR(glm::length(maxis - Vec3(-axis.x, axis.y, axis.z)), 0.0, 1e-12);
}

// A wavy carving stroke off the centre, crossing the +z face.
std::vector<ToolSample> stroke(ToolOp op, const Symmetry& sym) {
    std::vector<ToolSample> s(40);
    for (int i = 0; i < 40; ++i) {
        const double u = i / 39.0;
        s[i].t_s = i * 1e-3;
        s[i].position = Vec3(0.012 + 0.025 * u, -0.02 + 0.03 * u, 0.047 - 0.005 * std::sin(4.0 * u));
        s[i].orientation = glm::normalize(Quat(0.95, 0.2 * u, 0.1, -0.05));
        s[i].tool.kind = ToolKind::kFlatEnd;
        s[i].tool.radius_m = 0.005;
        s[i].tool.length_m = 0.02;
        s[i].op = op;
        s[i].material = 2;
        s[i].symmetry = sym;
    }
    return s;
}

// The stroke applied with symmetry (sample_sweeps), and the stroke plus each copy applied one sweep at a time,
// the copies made by hand: centre + T (p - centre) for the ends, T axis for the axis.
void expect_symmetric_apply_is_the_copies(const char* name, ToolOp op) {
    const Symmetry sym = parse_symmetry(name, "t");
    const std::vector<ToolSample> s = stroke(op, sym);
    TriDexel with = box_model(), explicit_copies = box_model();
    const Vec3 c = symmetry_centre(with.lattice);
    std::vector<Sweep> batch;
    for (std::size_t i = 1; i < s.size(); ++i)
        ASSERT_EQ(sample_sweeps(s[i - 1], s[i], nullptr, nullptr, c, batch), static_cast<std::size_t>(sym.copies()));
    for (const Sweep& sw : batch) apply_sweep(with, sw);
    const std::vector<SymmetryTransform> ts = symmetry_transforms(sym);
    for (std::size_t i = 1; i < s.size(); ++i) {
        Sweep sw;
        ASSERT_TRUE(sample_sweep(s[i - 1], s[i], nullptr, sw));
        for (const SymmetryTransform& t : ts) {
            Sweep copy = sw;
            copy.path_m = Segment{c + t.linear * (sw.path_m.a - c), c + t.linear * (sw.path_m.b - c)};
            copy.axis = t.linear * sw.axis;
            apply_sweep(explicit_copies, copy);
        }
    }
    EXPECT_EQ(model_digest(with), model_digest(explicit_copies)) << name;
    TriDexel plain = box_model();
    for (std::size_t i = 1; i < s.size(); ++i) {
        Sweep sw;
        ASSERT_TRUE(sample_sweep(s[i - 1], s[i], nullptr, sw));
        apply_sweep(plain, sw);
    }
    EXPECT_NE(model_digest(with), model_digest(plain)) << name;
}

TEST(Symmetry, AMirroredCutIsTheCutOfTheMirroredPoses) {
    for (const char* name : {"x", "y", "xy", "xyz"}) expect_symmetric_apply_is_the_copies(name, ToolOp::kSubtract);
    expect_symmetric_apply_is_the_copies("x", ToolOp::kUnion);
    expect_symmetric_apply_is_the_copies("xz", ToolOp::kPaint);
}

TEST(Symmetry, RadialCopiesAreTheCutsOfTheTurnedPosesAndRemoveNTimesTheVolume) {
    expect_symmetric_apply_is_the_copies("radial:5:z", ToolOp::kSubtract);
    expect_symmetric_apply_is_the_copies("radial:3:y", ToolOp::kUnion);
    // One short cut off the axis, and 6 copies of it about z: 6 times the volume (they do not overlap).
    TriDexel one = box_model(), six = box_model();
    const double v0 = dexel_volume_m3(one);
    ToolSample a, b;
    a.position = Vec3(0.03, 0.0, 0.045);
    b.position = Vec3(0.034, 0.002, 0.045);
    a.tool.radius_m = b.tool.radius_m = 0.006;
    a.op = b.op = ToolOp::kSubtract;
    Sweep sw;
    ASSERT_TRUE(sample_sweep(a, b, nullptr, sw));
    apply_sweep(one, sw);
    b.symmetry = parse_symmetry("radial:6:z", "t");
    std::vector<Sweep> batch;
    ASSERT_EQ(sample_sweeps(a, b, nullptr, nullptr, symmetry_centre(six.lattice), batch), 6u);
    for (const Sweep& s : batch) apply_sweep(six, s);
    const double removed1 = v0 - dexel_volume_m3(one), removed6 = v0 - dexel_volume_m3(six);
    EXPECT_GT(removed1, 0.0);
    EXPECT_NEAR(removed6 / removed1, 6.0, 0.06);
    std::printf("[symmetry] radial:6:z: removed volume %.4f times one cut's\n", removed6 / removed1);
}

// Length of the symmetric difference of two sorted interval lists on one ray (grid units).
double xor_length(std::vector<std::pair<double, double>> a, std::vector<std::pair<double, double>> b) {
    std::vector<std::pair<double, int>> ev;
    for (auto& [lo, hi] : a) ev.insert(ev.end(), {{lo, 1}, {hi, -1}});
    for (auto& [lo, hi] : b) ev.insert(ev.end(), {{lo, 2}, {hi, -2}});
    std::sort(ev.begin(), ev.end());
    int ina = 0, inb = 0;
    double len = 0.0, at = 0.0;
    for (const auto& [x, k] : ev) {
        if ((ina > 0) != (inb > 0)) len += x - at;
        at = x;
        if (std::abs(k) == 1) ina += k; else inb += k / 2;
    }
    return len;
}

// Largest symmetric-difference length (grid units) between each ray and its mirror image under `mirrors`.
double mirror_mismatch(const TriDexel& m, std::uint8_t mirrors) {
    double worst = 0.0;
    const auto flip = [&](int axis) { return (mirrors >> axis) & 1u; };
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = m.sets[a];
        const int ua = (a + 1) % 3, va = (a + 2) % 3, na = m.lattice.cells[a];
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u) {
                const int mu = flip(ua) ? m.lattice.cells[ua] - u : u, mv = flip(va) ? m.lattice.cells[va] - v : v;
                std::vector<std::pair<double, double>> here, there;
                for (const Interval& i : set.ray(u, v)) here.push_back({i.enter, i.exit});
                for (const Interval& i : set.ray(mu, mv))
                    there.push_back(flip(a) ? std::pair<double, double>{na - i.exit, na - i.enter}
                                            : std::pair<double, double>{i.enter, i.exit});
                std::sort(there.begin(), there.end());
                worst = std::max(worst, xor_length(here, there));
            }
    }
    return worst;
}

TEST(Symmetry, AMirroredCutLeavesAMirrorSymmetricModel) {
    for (const char* name : {"x", "yz", "xyz"}) {
        const Symmetry sym = parse_symmetry(name, "t");
        const std::vector<ToolSample> s = stroke(ToolOp::kSubtract, sym);
        TriDexel m = box_model();
        ASSERT_LT(mirror_mismatch(m, sym.mirrors), 1e-4);
        std::vector<Sweep> batch;
        for (std::size_t i = 1; i < s.size(); ++i)
            sample_sweeps(s[i - 1], s[i], nullptr, nullptr, symmetry_centre(m.lattice), batch);
        for (const Sweep& sw : batch) apply_sweep(m, sw);
        // Float chords computed from mirrored tool starts agree to a few ulps of the depths (40 cells).
        const double mismatch = mirror_mismatch(m, sym.mirrors);
        EXPECT_LT(mismatch, 1e-4) << name;
        std::printf("[symmetry] %s: largest difference between a ray and its mirror image %.3g cells\n", name, mismatch);
        // Without symmetry the same stroke is not mirror-symmetric.
        TriDexel one = box_model();
        for (std::size_t i = 1; i < s.size(); ++i) {
            Sweep sw;
            sample_sweep(s[i - 1], s[i], nullptr, sw);
            apply_sweep(one, sw);
        }
        EXPECT_GT(mirror_mismatch(one, sym.mirrors), 1.0) << name;
    }
}

// A mesh tool that is not its own mirror image (a wedge leaning toward +x): under mirror x the copy is cut with the
// reflected mesh, and the model is mirror-symmetric to within the mesh tool's sampling (a cell).
TEST(Symmetry, AMirroredMeshToolCutsWithTheMirrorImageOfTheMesh) {
    TriMesh wedge;
    wedge.positions = {Vec3(0.0, 0.0, 0.0), Vec3(0.012, 0.0, -0.004), Vec3(0.012, 0.0, 0.004), Vec3(0.004, 0.012, 0.0)};
    wedge.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    const std::shared_ptr<const MeshTool> tool = MeshTool::create(wedge, 4, "wedge");
    const std::shared_ptr<const MeshTool> mirror = mirrored_mesh_tool(*tool);
    EXPECT_EQ(mirror->mesh().positions[1], Vec3(-0.012, 0.0, -0.004));
    TriDexel m = box_model();
    ToolSample a, b;
    a.position = Vec3(0.015, -0.01, 0.046);
    b.position = Vec3(0.02, 0.01, 0.046);
    a.orientation = b.orientation = glm::angleAxis(-0.5 * std::numbers::pi, Vec3(1.0, 0.0, 0.0));  // +y onto -z
    a.tool = b.tool = ToolShape{ToolKind::kMesh, tool->bounding_radius_m(), 0.0, 0};
    a.op = b.op = ToolOp::kSubtract;
    b.symmetry = parse_symmetry("x", "t");
    std::vector<Sweep> batch;
    EXPECT_THROW(sample_sweeps(a, b, tool, nullptr, symmetry_centre(m.lattice), batch), Error);
    batch.clear();
    ASSERT_EQ(sample_sweeps(a, b, tool, mirror, symmetry_centre(m.lattice), batch), 2u);
    EXPECT_EQ(batch[1].tool.mesh, mirror);
    for (const Sweep& sw : batch) apply_sweep(m, sw);
    const double mesh_mismatch = mirror_mismatch(m, 1);
    EXPECT_LT(mesh_mismatch, 1.0);
    std::printf("[symmetry] mirrored mesh tool: largest ray difference %.3g cells\n", mesh_mismatch);
    // Cut with the unreflected mesh at the mirrored pose instead, the copy leans the wrong way.
    TriDexel wrong = box_model();
    batch[1].tool.mesh = tool;
    for (const Sweep& sw : batch) apply_sweep(wrong, sw);
    EXPECT_GT(mirror_mismatch(wrong, 1), 1.0);
}

}  // namespace
}  // namespace tridex::compute
