// Shift+digit chooses the material at the desk: a scripted mouse session paints one drag teal (the scene's
// material), presses Shift+5 and paints the next drag ochre (the scene's name for material 5). The recording keeps
// the change at the ticks that used it, the saved model holds both materials and the palette, and the replay
// sculpts the same model byte for byte.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "app/commands/replay/replay.hpp"
#include "app/session/run/run_session.hpp"
#include "compute/model/tdx_file.hpp"
#include "devices/recording.hpp"
#include "renderer/camera/off_axis.hpp"
#include "run_test_scene.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 192, kH = 144;
const Vec3 kEye(0.0, 0.05, 0.6);

// The pixel of a kW x kH desktop eye image where the ray from kEye through world point p meets the screen.
std::string cursor_at(double t_s, double x_m, double y_m, int buttons) {
    const renderer::Screen screen = renderer::Screen::desktop_monitor();
    const Vec3 p(x_m, y_m, 0.05);
    const Vec3 s = kEye + (p - kEye) * (kEye.z / (kEye.z - p.z));
    const double u = (s.x - screen.lower_left.x) / screen.width(), v = (s.y - screen.lower_left.y) / screen.height();
    return "{\"t_s\": " + std::to_string(t_s) + ", \"x_px\": " + std::to_string(u * kW) + ", \"y_px\": " +
           std::to_string((1.0 - v) * kH) + ", \"buttons\": " + std::to_string(buttons) + "}";
}

std::string write_scene(const fs::path& dir) {
    const std::string path = (dir / "colour_keys.json").string();
    std::ofstream(path) << R"({
  "workpiece": { "resolution": 64, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "device": { "driver": "mouse" },
  "op": "paint", "material": "teal",
  "materials": [{ "id": 2, "name": "teal", "colour": "#2a9d8f" }, { "id": 5, "name": "ochre", "colour": "#cc7722" }],
  "stroke": "none",
  "display": { "preset": "desktop", "resolution": [)" << kW << ", " << kH << R"(], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] },
  "cursor": [ )" << cursor_at(0.2, -0.02, 0.01, 0) << ", " << cursor_at(0.5, -0.02, 0.01, 1) << ", "
                   << cursor_at(1.1, 0.02, 0.01, 0) << ", " << cursor_at(1.3, -0.02, -0.01, 0) << ", "
                   << cursor_at(1.5, -0.02, -0.01, 1) << ", " << cursor_at(2.1, 0.02, -0.01, 0) << ", "
                   << cursor_at(2.3, 0.02, -0.01, 0) << R"( ],
  "keys": [{"t_s": 1.2, "press": "shift+5"}]
})";
    return path;
}

TEST(ColourKeys, ShiftDigitPaintsTheNextDragInAnotherColourAndReplays) {
    const fs::path dir = test::temp_dir("colour_keys");
    RunOptions o;
    o.scene = write_scene(dir);
    o.display = "offscreen";
    o.stereo = "mono";
    o.out = (dir / "run").string();
    o.record = (dir / "run.trdx").string();
    o.save = (dir / "run.tdx").string();
    o.no_journal = true;
    o.cpu = true;
    const RunResult r = run_stereo_session(o);
    EXPECT_EQ(r.notes.front(), "ended: the scripted cursor ended");

    // The recording: material 2 on the first drag's ticks, 5 from the key on.
    const devices::Recording rec = devices::read_recording(o.record);
    std::size_t teal = 0, ochre = 0;
    for (const devices::RecordedTick& t : rec.ticks) {
        teal += t.material == 2;
        ochre += t.material == 5;
    }
    EXPECT_GT(teal, 500u);
    EXPECT_GT(ochre, 500u);
    std::printf("recorded ticks: %zu teal, %zu ochre\n", teal, ochre);

    // The saved model: both materials on the surface, and the scene's palette.
    const compute::TdxModel saved = compute::load_tdx(o.save, std::size_t{1} << 30);
    EXPECT_EQ(saved.palette[5].name, "ochre");
    std::size_t ends[8] = {};
    for (const auto& set : saved.model.sets)
        for (const auto& ray : set.rays)
            for (const compute::Interval& iv : ray) ++ends[iv.enter_material & 7], ++ends[iv.exit_material & 7];
    EXPECT_GT(ends[2], 10u);
    EXPECT_GT(ends[5], 10u);
    std::printf("interval ends: %zu teal, %zu ochre\n", ends[2], ends[5]);

    OutputOptions out;
    out.out = (dir / "replay").string();
    out.width = 64;
    out.height = 48;
    run_replay(o.record, out, SculptOptions{true, false, false, false, ""});
    EXPECT_TRUE(test::bytes_of(dir / "run" / "sculpted.ply") == test::bytes_of(dir / "replay" / "sculpted.ply"))
        << "the replay painted a different model";
}

}  // namespace
}  // namespace tridex::app
