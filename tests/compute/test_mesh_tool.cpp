// tests/compute/test_mesh_tool.cpp - any closed mesh as a tool (ToolKind::kMesh), CPU reference: bad meshes
// refused, the shortest-arc orientation, cached tool dexels, zero-length segments, a tool larger than the
// workpiece, and the multi-threaded path equal to the sequential one.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "compute/tools/mesh_tool.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/tools/sweep.hpp"
#include "compute/tools/sweep_parallel.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

using namespace tridex;
using namespace tridex::compute;

namespace {

std::string shared_data() {
    const char* d = std::getenv("TRIDEX_SHARED_DATA");
    return d ? d : "../shared/data";
}

std::string refusal_of(TriMesh m) {
    try {
        MeshTool::create(std::move(m), 4, "t");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TriDexel box_model(int cells, double lo, double hi) {
    Lattice L;
    L.origin_m = Vec3(0.2, -0.1, 0.05);
    L.cell_m = 0.001;
    L.cells = {cells, cells, cells};
    TriDexel m = TriDexel::empty(L, std::size_t{1} << 30);
    if (hi > lo) scan_convert(box_mesh(Aabb{L.to_world(Vec3(lo)), L.to_world(Vec3(hi))}), m);
    return m;
}

bool same_rays(const TriDexel& a, const TriDexel& b) {
    for (int s = 0; s < 3; ++s)
        for (std::size_t i = 0; i < a.sets[s].rays.size(); ++i) {
            const auto &x = a.sets[s].rays[i], &y = b.sets[s].rays[i];
            if (x.size() != y.size()) return false;
            for (std::size_t k = 0; k < x.size(); ++k)
                if (x[k].enter != y[k].enter || x[k].exit != y[k].exit || x[k].enter_material != y[k].enter_material ||
                    x[k].exit_material != y[k].exit_material)
                    return false;
        }
    return true;
}

}  // namespace

TEST(MeshTool, BadMeshesAreRefusedWithTheReason) {
    const TriMesh box = box_mesh(Aabb{Vec3(-0.002), Vec3(0.002)});
    EXPECT_NE(refusal_of(TriMesh{}).find("no triangles"), std::string::npos);
    TriMesh open = box;
    open.triangles.pop_back();
    EXPECT_NE(refusal_of(open).find("not closed: 3 boundary edges"), std::string::npos) << refusal_of(open);
    TriMesh nonmanifold = box;
    auto t = box.triangles[0];
    std::swap(t[1], t[2]);
    nonmanifold.triangles.push_back(t);  // a reversed copy: its three edges are used three times
    EXPECT_NE(refusal_of(nonmanifold).find("non-manifold"), std::string::npos) << refusal_of(nonmanifold);
    TriMesh flipped_one = box;
    std::swap(flipped_one.triangles[3][1], flipped_one.triangles[3][2]);
    EXPECT_NE(refusal_of(flipped_one).find("misoriented"), std::string::npos) << refusal_of(flipped_one);
    TriMesh repeated = box;
    repeated.triangles[0][1] = repeated.triangles[0][0];
    EXPECT_NE(refusal_of(repeated).find("degenerate"), std::string::npos) << refusal_of(repeated);
    TriMesh nan = box;
    nan.positions[2].y = NAN;
    EXPECT_NE(refusal_of(nan).find("not finite"), std::string::npos);
    TriMesh index = box;
    index.triangles[5][2] = 99;
    EXPECT_NE(refusal_of(index).find("out of range"), std::string::npos);
    // A closed, oriented mesh with zero-area triangles: a box squashed flat (its side faces collapse).
    TriMesh flat = box_mesh(Aabb{Vec3(0.0), Vec3(1.0)});
    for (Vec3& p : flat.positions) p.z *= 1e-20;  // all four side faces collapse
    EXPECT_NE(refusal_of(flat).find("zero-area"), std::string::npos) << refusal_of(flat);
    EXPECT_THROW(MeshTool::create(box, 0), Error);
    EXPECT_THROW(MeshTool::create(box, 17), Error);
    // Inside-out meshes are turned outward, not refused.
    TriMesh inside_out = box;
    for (auto& tri : inside_out.triangles) std::swap(tri[1], tri[2]);
    const auto tool = MeshTool::create(inside_out);
    EXPECT_GT(signed_volume(tool->mesh()), 0.0);
}

TEST(MeshTool, BadAndOpenMeshFilesAreRefusedWithTheirPath) {
    namespace fs = std::filesystem;
    std::size_t files = 0;
    for (const auto& entry : fs::directory_iterator(shared_data() + "/bad")) {
        const std::string path = entry.path().string();
        try {
            MeshTool::load(path, 0.001);
            ADD_FAILURE() << path << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind(path, 0), 0u) << e.what();
        }
        ++files;
    }
    EXPECT_GE(files, 6u);
    const std::string open = shared_data() + "/meshes/elephant-with-holes.off";
    try {
        MeshTool::load(open, 0.001);
        ADD_FAILURE() << "open elephant accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
    }
    EXPECT_THROW(MeshTool::load(shared_data() + "/meshes/sphere.off", -1.0), Error);
    const auto sphere = MeshTool::load(shared_data() + "/meshes/sphere.off", 0.001);
    EXPECT_GT(sphere->bounding_radius_m(), 0.0);
}

TEST(MeshTool, ShortestArcRotationTurnsZOntoTheAxis) {
    std::mt19937 rng(3);
    std::normal_distribution<double> g;
    std::vector<Vec3> axes{{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0, 0, -5}, {1e-9, 0, -1}};
    for (int i = 0; i < 50; ++i) axes.emplace_back(g(rng), g(rng), g(rng));
    for (const Vec3& a : axes) {
        const glm::dmat3 R = tool_rotation(a);
        const Vec3 z = R * Vec3(0, 0, 1);
        EXPECT_LT(glm::length(z - glm::normalize(a)), 1e-12);
        EXPECT_NEAR(glm::determinant(R), 1.0, 1e-12);
        const glm::dmat3 I = glm::transpose(R) * R;
        for (int c = 0; c < 3; ++c)
            for (int r = 0; r < 3; ++r) EXPECT_NEAR(I[c][r], c == r ? 1.0 : 0.0, 1e-12);
        // Shortest arc: vectors perpendicular to both z and the axis are left alone.
        const Vec3 w = glm::cross(Vec3(0, 0, 1), glm::normalize(a));
        if (glm::length(w) > 1e-6) {
            EXPECT_LT(glm::length(R * w - w), 1e-12);
        }
    }
    EXPECT_THROW(tool_rotation(Vec3(0.0)), Error);
    EXPECT_THROW(tool_rotation(Vec3(NAN, 0, 1)), Error);
}

TEST(MeshTool, ToolDexelsAreCachedPerOrientationAndCellSize) {
    const auto tool = MeshTool::create(icosphere_mesh(Vec3(0.0), 0.003, 2));
    const auto a = tool->dexels(Vec3(0, 0, 1), 0.001);
    EXPECT_EQ(a, tool->dexels(Vec3(0, 0, 2), 0.001));  // the axis is normalised
    EXPECT_NE(a, tool->dexels(Vec3(0, 1, 1), 0.001));
    EXPECT_NE(a, tool->dexels(Vec3(0, 0, 1), 0.0005));
    EXPECT_EQ(a->k, 4);
    // The reference point (centre) ray of each set holds one interval of about the diameter, 6 cells.
    for (int s = 0; s < 3; ++s) {
        const ToolDexelSet& set = a->sets[s];
        const std::size_t ray = static_cast<std::size_t>(set.ref_u) + static_cast<std::size_t>(set.nu) * set.ref_v;
        ASSERT_EQ(set.first[ray + 1] - set.first[ray], 1u);
        EXPECT_NEAR(set.depth[2 * set.first[ray]], -3.0, 1e-6);
        EXPECT_NEAR(set.depth[2 * set.first[ray] + 1], 3.0, 1e-6);
    }
    EXPECT_THROW(tool->dexels(Vec3(0, 0, 1), 0.0), Error);
    EXPECT_THROW(tool->dexels(Vec3(0.0), 0.001), Error);
    // What a cache miss costs (a new orientation): a 5120-triangle ball of radius 8 cells at k = 4.
    const auto ball = MeshTool::create(icosphere_mesh(Vec3(0.0), 0.008, 4));
    const auto t0 = std::chrono::steady_clock::now();
    const auto d = ball->dexels(Vec3(0.1, 0.2, 1.0), 0.001);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "tool dexels of a 5120-triangle ball, radius 8 cells, k = 4: " << d->interval_count() << " intervals, "
              << ms << " ms to build\n";
    EXPECT_GT(d->interval_count(), 3000u);
}

TEST(MeshTool, SweepsNeedAMeshAndATable) {
    TriDexel m = box_model(24, 4.0, 20.0);
    Sweep s;
    s.tool.kind = ToolKind::kMesh;
    s.path_m = Segment{m.lattice.to_world(Vec3(12.0)), m.lattice.to_world(Vec3(12.0))};
    EXPECT_THROW(apply_sweep(m, s), Error);  // no mesh
    s.tool.mesh = MeshTool::create(icosphere_mesh(Vec3(0.0), 0.003, 2));
    EXPECT_THROW(to_grid_sweep(m.lattice, s), Error);  // no table to put the tool's dexels in
    s.axis = Vec3(0.0);
    EXPECT_THROW(apply_sweep(m, s), Error);
}

TEST(MeshTool, ZeroLengthSegmentStampsTheToolOnceAtItsReferencePoint) {
    // A box tool whose faces lie on half-cell planes, placed on a node: the hole is exactly the box.
    TriDexel m = box_model(32, 4.0, 28.0);
    const double c = m.lattice.cell_m;
    Sweep s;
    s.tool.kind = ToolKind::kMesh;
    s.tool.mesh = MeshTool::create(box_mesh(Aabb{Vec3(-2.5, -3.5, -1.5) * c, Vec3(2.5, 3.5, 4.5) * c}));
    const Vec3 at(16.0, 15.0, 17.0);
    s.path_m = Segment{m.lattice.to_world(at), m.lattice.to_world(at)};
    s.material = 3;
    const BooleanStats st = apply_sweep(m, s);
    EXPECT_GT(st.rays_changed, 0u);
    // Z ray through (16, 15): cut from 15.5 to 21.5 with material 3 on the cut ends.
    const auto& z = m.sets[2].ray(16, 15);
    ASSERT_EQ(z.size(), 2u);
    EXPECT_EQ(z[0].exit, 15.5f);
    EXPECT_EQ(z[1].enter, 21.5f);
    EXPECT_EQ(z[0].exit_material, 3);
    // X ray through (y, z) = (15, 17): cut over x in [13.5, 18.5]; the ray at y = 19 misses (box reaches 18.5).
    const auto& x = m.sets[0].ray(15, 17);
    ASSERT_EQ(x.size(), 2u);
    EXPECT_EQ(x[0].exit, 13.5f);
    EXPECT_EQ(x[1].enter, 18.5f);
    EXPECT_EQ(m.sets[0].ray(19, 17).size(), 1u);
    EXPECT_EQ(m.sets[0].ray(18, 17).size(), 2u);
}

TEST(MeshTool, ToolLargerThanTheWorkpieceRemovesOrFillsItAll) {
    TriDexel m = box_model(20, 3.0, 17.0);
    Sweep s;
    s.tool.kind = ToolKind::kMesh;
    s.tool.mesh = MeshTool::create(icosphere_mesh(Vec3(0.0), 0.030, 3), 2);  // radius 30 cells
    s.axis = Vec3(0.3, -0.2, 1.0);
    s.path_m = Segment{m.lattice.to_world(Vec3(10.0)), m.lattice.to_world(Vec3(11.0, 10.0, 9.0))};
    s.op = ToolOp::kUnion;
    s.material = 2;
    apply_sweep(m, s);
    for (int a = 0; a < 3; ++a)
        for (const auto& r : m.sets[a].rays) {
            ASSERT_EQ(r.size(), 1u);
            EXPECT_TRUE(std::isfinite(r[0].enter) && std::isfinite(r[0].exit));
            EXPECT_LE(r[0].enter, 0.0f);
            EXPECT_GE(r[0].exit, 20.0f);
        }
    s.op = ToolOp::kSubtract;
    apply_sweep(m, s);
    EXPECT_EQ(m.interval_count(), 0u);
}

TEST(MeshTool, ParallelPathEqualsSequentialForMixedTools) {
    TriDexel seq = box_model(40, 6.0, 34.0);
    TriDexel par = box_model(40, 6.0, 34.0);
    const double c = seq.lattice.cell_m;
    TriMesh dumbbell = box_mesh(Aabb{Vec3(-2.0, -1.0, -1.0) * c, Vec3(-0.5, 1.0, 1.0) * c});
    const TriMesh right = box_mesh(Aabb{Vec3(0.7, -1.2, -1.0) * c, Vec3(2.2, 1.0, 1.3) * c});
    for (auto t : right.triangles) {
        for (auto& i : t) i += static_cast<std::uint32_t>(dumbbell.positions.size());
        dumbbell.triangles.push_back(t);
    }
    dumbbell.positions.insert(dumbbell.positions.end(), right.positions.begin(), right.positions.end());
    const auto tool = MeshTool::create(dumbbell);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> pos(8.0, 32.0), unit(0.0, 1.0);
    std::vector<Sweep> batch;
    for (int i = 0; i < 60; ++i) {
        Sweep s;
        s.op = i % 3 == 0 ? ToolOp::kUnion : i % 3 == 1 ? ToolOp::kSubtract : ToolOp::kPaint;
        s.material = static_cast<std::uint8_t>(1 + i % 5);
        if (i % 4 == 3) s.tool = SweepTool{ToolKind::kBall, 2.2 * c, 0.0};
        else s.tool = SweepTool{ToolKind::kMesh, 0.0, 0.0, tool};
        s.axis = Vec3(unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5 + (i % 2 ? 2.0 : 0.0));
        const Vec3 a(pos(rng), pos(rng), pos(rng));
        s.path_m = Segment{seq.lattice.to_world(a), seq.lattice.to_world(a + Vec3(unit(rng), unit(rng), unit(rng)) * 4.0)};
        batch.push_back(s);
    }
    std::size_t changed = 0;
    for (const Sweep& s : batch) changed += apply_sweep(seq, s).rays_changed;
    const BooleanStats p = apply_sweeps_parallel(par, batch, 2);
    EXPECT_EQ(p.rays_changed, changed);
    EXPECT_GT(changed, 1000u);
    EXPECT_TRUE(same_rays(seq, par));
    // The non-convex tool leaves rays with more intervals than the box had.
    std::size_t multi = 0;
    for (int a = 0; a < 3; ++a)
        for (const auto& r : seq.sets[a].rays) multi += r.size() > 2;
    EXPECT_GT(multi, 0u);
}
