// `tridex resample MODEL --resolution N --out NEW`: the executable writes the model at the new resolution with its
// palette and settings, prints what changed, and refuses bad input in one line naming the file or option.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "compute/tools/model_resample.hpp"
#include "run_test_scene.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

/// A ball of radius 0.04 m on a 48-cell lattice, its top half painted material 3, built ray by ray from exact chords.
compute::TriDexel painted_ball() {
    const compute::Lattice L = compute::Lattice::around(Aabb{Vec3(-0.05), Vec3(0.05)}, 48);
    compute::TriDexel m = compute::TriDexel::empty(L, std::size_t{1} << 30);
    const double r = 0.04;
    for (int a = 0; a < 3; ++a) {
        compute::RaySet& set = m.sets[a];
        for (int v = 0; v < set.nv; ++v)
            for (int u = 0; u < set.nu; ++u) {
                Vec3 g(0.0);
                g[(a + 1) % 3] = u;
                g[(a + 2) % 3] = v;
                const Vec3 p = L.to_world(g);
                const double h2 = r * r - (glm::dot(p, p) - p[a] * p[a]);
                if (!(h2 > 0.0)) continue;
                compute::Interval iv;
                iv.enter = static_cast<float>((-std::sqrt(h2) - L.origin_m[a]) / L.cell_m);
                iv.exit = static_cast<float>((std::sqrt(h2) - L.origin_m[a]) / L.cell_m);
                const double ze = a == 2 ? -std::sqrt(h2) : p.z, zx = a == 2 ? std::sqrt(h2) : p.z;  // ends' heights
                iv.enter_material = ze > 0.0 ? 3 : 0;
                iv.exit_material = zx > 0.0 ? 3 : 0;
                set.ray(u, v).push_back(iv);
            }
    }
    return m;
}

/// Saves painted_ball() with a renamed material 3 and settings naming resolution 48 into `dir`; returns its path.
std::string save_ball(const fs::path& dir, compute::TriDexel& model, MaterialPalette& palette) {
    model = painted_ball();
    palette = default_material_palette();
    palette.entries[3].name = "glaze";
    const std::string path = (dir / "ball.tdx").string();
    compute::save_tdx(path, model, Mat4(1.0), R"({"resolution":48,"stock_m":0.1})", 3, palette);
    return path;
}

TEST(ResampleCommand, WritesTheModelAtTheNewResolutionAndSaysWhatChanged) {
    const fs::path dir = test::temp_dir("resample_cmd");
    compute::TriDexel model;
    MaterialPalette palette;
    const std::string in = save_ball(dir, model, palette);
    const std::string out = (dir / "fine.tdx").string();
    const test::ExeResult r = test::run_tridex("resample " + in + " --resolution 72 --out " + out, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string said = test::bytes_of(dir / "stdout.txt");
    EXPECT_NE(said.find("resolution 48"), std::string::npos) << said;
    EXPECT_NE(said.find("resolution 72"), std::string::npos) << said;
    EXPECT_NE(said.find("volume:"), std::string::npos) << said;
    EXPECT_NE(said.find("largest surface move:"), std::string::npos) << said;
    EXPECT_NE(said.find("cells of the coarser lattice"), std::string::npos) << said;
    EXPECT_NE(said.find("MiB"), std::string::npos) << said;
    const compute::TdxModel back = compute::load_tdx(out, std::size_t{1} << 30);
    EXPECT_EQ(compute::lattice_resolution(back.model.lattice), 72);
    EXPECT_EQ(back.palette, palette);
    EXPECT_EQ(nlohmann::json::parse(back.settings_json).at("resolution"), 72);
    const double v0 = compute::dexel_volume_m3(model), v1 = compute::dexel_volume_m3(back.model);
    EXPECT_NEAR(v1, v0, 0.01 * v0);
    bool has3 = false;
    for (const auto& ray : back.model.sets[2].rays)
        for (const compute::Interval& iv : ray) has3 = has3 || iv.exit_material == 3;
    EXPECT_TRUE(has3);
    fs::remove_all(dir);
}

/// Runs `tridex resample ARGS` in `dir` and expects exit 2 with one stderr line holding every one of `parts`.
void expect_refused(const std::string& args, const fs::path& dir, std::initializer_list<std::string> parts) {
    const test::ExeResult r = test::run_tridex("resample " + args, dir);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.err;
    for (const std::string& p : parts) EXPECT_NE(r.err.find(p), std::string::npos) << args << ": " << r.err;
}

TEST(ResampleCommand, RefusesBadInputInOneLineNamingIt) {
    const fs::path dir = test::temp_dir("resample_refuse");
    compute::TriDexel model;
    MaterialPalette palette;
    const std::string in = save_ball(dir, model, palette);
    const std::string out = (dir / "x.tdx").string();
    expect_refused((dir / "missing.tdx").string() + " --resolution 64 --out " + out, dir, {"missing.tdx"});
    const std::string junk = (dir / "junk.tdx").string();
    std::ofstream(junk) << "not a model";
    expect_refused(junk + " --resolution 64 --out " + out, dir, {"junk.tdx"});
    expect_refused(in + " --resolution sixty --out " + out, dir, {"--resolution", "'sixty'"});
    expect_refused(in + " --resolution 5000 --out " + out, dir, {"--resolution", "between 8 and 4096", "5000"});
    expect_refused(in + " --resolution 64 --out /proc/nowhere/x.tdx", dir, {"--out", "/proc/nowhere/x.tdx"});
    expect_refused(in + " --resolution 64 --out " + in, dir, {"--out", "ball.tdx"});
    EXPECT_FALSE(fs::exists(out));
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
