// `tridex export`: a saved model written as STL, OBJ and PLY, in metres and millimetres, reloads as a closed mesh
// whose volume is the model's tri-dexel volume within the contouring's error; bad inputs are refused in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "app/commands/export/export.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "compute/mesh/mesh_io.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/sweep.hpp"
#include "core/error.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

double area_m2(const TriMesh& m) {
    double a = 0.0;
    for (const auto& t : m.triangles)
        a += 0.5 * glm::length(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
    return a;
}

/// The bundled bunny at `n` cells (0.3 m), carved by a few ball and flat-end strokes, saved to `path`.
compute::TriDexel carved_bunny(int n, const std::string& path) {
    const char* assets = std::getenv("TRIDEX_ASSETS");
    Workpiece wp = prepare_workpiece((fs::path(assets ? assets : "assets") / "bunny.off").string(), n, 0.3,
                                     Vec3(0.0, 0.0, 0.3));
    const Aabb box = wp.model.lattice.bounds();
    compute::Sweep s;
    s.tool = compute::SweepTool{ToolKind::kBall, 0.012, 0.0};
    s.path_m = Segment{Vec3(box.lo.x, 0.0, 0.33), Vec3(box.hi.x, 0.02, 0.33)};
    compute::apply_sweep(wp.model, s);
    s.tool = compute::SweepTool{ToolKind::kFlatEnd, 0.01, 0.03};
    s.op = ToolOp::kPaint;
    s.material = 3;
    s.path_m = Segment{Vec3(0.0, box.hi.y, 0.3), Vec3(0.0, box.lo.y, 0.3)};
    compute::apply_sweep(wp.model, s);
    compute::save_tdx(path, wp.model, wp.to_world, "{}");
    return wp.model;
}

TEST(Export, EveryFormatReloadsClosedWithTheModelsVolume) {
    const fs::path dir = test::temp_dir("export");
    const std::string model_path = (dir / "bunny.tdx").string();
    const compute::TriDexel model = carved_bunny(96, model_path);
    const double h = model.lattice.cell_m, dexel = compute::dexel_volume_m3(model);
    for (const char* name : {"bunny.stl", "bunny.obj", "bunny.ply", "bunny_mm.stl"}) {
        ExportOptions o;
        o.model = model_path;
        o.out = (dir / name).string();
        o.units = std::string(name).find("_mm") != std::string::npos ? "mm" : "m";
        const ExportResult r = run_export(o);
        EXPECT_EQ(r.boundary_edges, 0u);
        EXPECT_DOUBLE_EQ(r.volume_dexel_m3, dexel);
        const TriMesh back = compute::load_closed_mesh(o.out);  // throws unless closed and consistently oriented
        const double scale = o.units == "mm" ? 1e-3 : 1.0;
        EXPECT_EQ(edge_stats(back).boundary_edges, 0u);
        EXPECT_EQ(back.triangles.size(), r.triangles) << name;
        const double volume = signed_volume(back) * scale * scale * scale, area = area_m2(back) * scale * scale;
        // The contoured surface and the dexel volume's surface both lie within a cell of the true one; the volumes
        // differ by the mean signed offset between the two surfaces times the area A. Measured here:
        // |dV| / (A h) = 0.003 (carved bunny, N = 96; 4e-4 of the volume). The bound 0.05 (a twentieth of a cell on
        // average) leaves room for other shapes and still catches a mesh shifted by half a cell (0.5) or
        // written at the wrong scale.
        const double offset_cells = std::abs(volume - dexel) / (area * h);
        EXPECT_LT(offset_cells, 0.05) << name << ": mesh " << volume << " m^3, dexel " << dexel << " m^3, area " << area;
        std::printf("%s: %zu triangles, volume %.9g m^3 (dexel %.9g), |dV|/(A h) = %.4f\n", name, r.triangles, volume,
                    dexel, offset_cells);
    }
    // Binary STL: 84 + 50 per triangle bytes.
    EXPECT_EQ(fs::file_size(dir / "bunny.stl"), 84 + 50 * compute::load_closed_mesh((dir / "bunny.stl").string()).triangles.size());
}

// --frame input undoes the model's placement: the export lies over the mesh it was carved from (an uncarved model's
// bounds are the input mesh's within a cell, in the mesh's own units); --units in writes inches.
TEST(Export, TheInputFrameLinesUpWithTheInputMeshAndInchesScale) {
    const fs::path dir = test::temp_dir("export_frame");
    const char* assets = std::getenv("TRIDEX_ASSETS");
    const std::string mesh_path = (fs::path(assets ? assets : "assets") / "bunny.off").string();
    Workpiece wp = prepare_workpiece(mesh_path, 64, 0.3, Vec3(0.0, 0.0, 0.3));
    const std::string model_path = (dir / "bunny.tdx").string();
    compute::save_tdx(model_path, wp.model, wp.to_world, "{}");
    ExportOptions o;
    o.model = model_path;
    o.out = (dir / "input.stl").string();
    o.frame = "input";
    (void)run_export(o);
    const Aabb in = compute::load_closed_mesh(mesh_path).bounds();
    const Aabb out = compute::load_closed_mesh(o.out).bounds();
    // A world cell in the mesh's units: the placement's scale is stock / the mesh's largest extent.
    const Vec3 ext = in.hi - in.lo;
    const double cell_in = wp.model.lattice.cell_m / (0.3 / std::max({ext.x, ext.y, ext.z}));
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(out.lo[a], in.lo[a], cell_in) << "axis " << a;
        EXPECT_NEAR(out.hi[a], in.hi[a], cell_in) << "axis " << a;
    }
    // Inches: the world mesh scaled by 1 / 0.0254.
    o.frame = "world";
    o.units = "in";
    o.out = (dir / "inches.stl").string();
    (void)run_export(o);
    o.units = "m";
    o.out = (dir / "metres.stl").string();
    (void)run_export(o);
    const Aabb inches = compute::load_closed_mesh((dir / "inches.stl").string()).bounds();
    const Aabb metres = compute::load_closed_mesh((dir / "metres.stl").string()).bounds();
    EXPECT_NEAR(inches.hi.x * 0.0254, metres.hi.x, 1e-6);
    EXPECT_NEAR(inches.lo.y * 0.0254, metres.lo.y, 1e-6);
    // The input frame keeps the mesh's units: another unit with it is refused.
    o.frame = "input";
    o.units = "mm";
    EXPECT_THROW((void)run_export(o), Error);
    fs::remove_all(dir);
}

TEST(Export, BadInputsAreRefusedAndLeaveNoFile) {
    const fs::path dir = test::temp_dir("export_bad");
    const std::string model_path = (dir / "m.tdx").string();
    carved_bunny(32, model_path);
    auto refusal = [&](const std::string& model, const std::string& out, const std::string& units = "m") {
        try {
            run_export(ExportOptions{model, out, units});
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(refusal(model_path, (dir / "x.xyz").string()).find("unknown mesh format '.xyz'"), std::string::npos);
    EXPECT_NE(refusal(model_path, (dir / "noext").string()).find("no file extension to tell the mesh format"),
              std::string::npos);
    EXPECT_NE(refusal(model_path, (dir / "x.stl").string(), "km").find("--units"), std::string::npos);
    std::ofstream(dir / "junk.tdx") << "junk";
    EXPECT_NE(refusal((dir / "junk.tdx").string(), (dir / "x.stl").string()).find("bad magic"), std::string::npos);
    EXPECT_FALSE(fs::exists(dir / "x.stl"));
    EXPECT_FALSE(fs::exists(dir / "x.xyz"));
}

}  // namespace
}  // namespace tridex::app
