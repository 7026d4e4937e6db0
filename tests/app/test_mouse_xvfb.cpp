// `tridex run --display window --device mouse` under a private Xvfb, driven by real X input events (xdotool, through
// the XTEST extension): a left-button drag across the workpiece carves a groove where the cursor went (the saved
// model's surface, seen through the cursor's pixels, is deeper along the path and unchanged beside it), Ctrl+Z
// takes it back, a right-button drag moves the workspace, Esc closes the window and the report is written; with the M
// key symmetry goes on and a drag on one side carves its mirror image on the other. Skipped only when the Xvfb or xdotool binary is missing.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "../renderer/test_window_xvfb.hpp"
#include "../test_paths.hpp"
#include "app/input/surface_pick.hpp"
#include "app/session/batch/session.hpp"
#include "app/session/view/framing.hpp"
#include "app/support/memory.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "run_test_scene.hpp"
#include "test_files.hpp"
#include "xvfb_session.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using test::have_binary;
using test::wait_for;
using test::xdo;

constexpr int kW = 400, kH = 300;  // the window: one mono eye image
const Vec3 kEye(0.0, 0.05, 0.6);
// The screen the window shows: the desk monitor cropped to frame the workpiece (a desk window with a fixed head),
// set from the first saved model's lattice.
renderer::Screen kScreen = renderer::Screen::desktop_monitor();
const Vec3 kFrom(-0.025, 0.0, 0.05), kTo(0.025, 0.0, 0.05);  // the drag, world m

// The pixel of the window where the ray from kEye through world point p crosses the screen.
std::pair<int, int> pixel_of(const Vec3& p) {
    const Vec3 s = kEye + (p - kEye) * (kEye.z / (kEye.z - p.z));
    const double u = (s.x - kScreen.lower_left.x) / kScreen.width();
    const double v = (s.y - kScreen.lower_left.y) / kScreen.height();
    return {static_cast<int>(std::lround(u * kW)), static_cast<int>(std::lround((1.0 - v) * kH))};
}

ino_t inode_of(const fs::path& p) {
    struct stat st {};
    return ::stat(p.c_str(), &st) == 0 ? st.st_ino : 0;
}

// The saved model's surface, contoured on the CPU as `tridex export` does.
struct Saved {
    PickSurface surface;
    double volume_m3 = 0.0;
};
Saved load_saved(const fs::path& tdx) {
    compute::TdxModel saved = compute::load_tdx(tdx.string(), model_memory_budget_bytes());
    std::fill(saved.model.tiles.dirty.begin(), saved.model.tiles.dirty.end(), std::uint8_t{1});
    compute::Contourer contourer(saved.model);
    contourer.update(saved.model);
    Saved s;
    s.surface.whole = std::make_shared<const TriMesh>(contourer.mesh());
    s.volume_m3 = compute::dexel_volume_m3(saved.model);
    return s;
}

// How far the ray through the pixel of world point p (moved dy_px down) travels to the surface, m; NaN: a miss.
double ray_depth(const Saved& s, const Vec3& p, double dy_px = 0.0) {
    const auto [x, y] = pixel_of(p);
    const std::optional<Ray> ray = cursor_ray(kScreen, kEye, x + 0.5, y + 0.5 + dy_px, kW, kH);
    if (!ray) return std::numeric_limits<double>::quiet_NaN();
    const std::optional<SurfaceHit> hit = pick_surface(s.surface, *ray);
    return hit ? hit->distance_m : std::numeric_limits<double>::quiet_NaN();
}

// Writes the desk scene (the bunny, a mouse, no stroke, a fixed head) into `dir` and returns the `run` arguments that
// open it in a mono window, saving with Ctrl+S to `save` and writing the report to `out`.
std::string mouse_run_args(const fs::path& dir, const fs::path& out, const fs::path& save) {
    const std::string scene = (dir / "scene.json").string();
    std::ofstream(scene) << R"({
  "workpiece": { "resolution": 64, "stock_m": 0.12, "centre_m": [0.0, 0.0, 0.05] },
  "tool": { "radius_m": 0.006 },
  "device": { "driver": "mouse" },
  "stroke": "none",
  "display": { "preset": "desktop", "resolution": [)" << kW << ", " << kH << R"(], "refresh_hz": 60 },
  "head": { "provider": "fixed", "position_m": [0.0, 0.05, 0.6] }
}
)";
    return "run " + scene + " --display window --stereo mono --device mouse --cpu --no-journal --out " + out.string() +
           " --save " + save.string();
}

TEST(MouseXvfb, RealXEventsCarveUndoMoveTheWorkspaceAndClose) {
    if (!have_binary("Xvfb") || !have_binary("xdotool"))
        GTEST_SKIP() << "needs the Xvfb and xdotool binaries (scripts/install-deps.sh installs xvfb and xdotool)";
    renderer::test::VirtualDisplay display(800, 600);
    const fs::path dir = test::temp_dir("mouse_xvfb");
    const fs::path out = dir / "out", save = dir / "live.tdx";
    test::TridexProcess app(TRIDEX_EXE, mouse_run_args(dir, out, save), dir);
    const std::string w = test::find_window("tridex run");
    ASSERT_FALSE(w.empty());
    const auto move_to = [&](const Vec3& p) {
        const auto [x, y] = pixel_of(p);
        xdo("mousemove --window " + w + " " + std::to_string(x) + " " + std::to_string(y));
    };
    // Ctrl+S, then wait for the save (a new file: the save renames a temporary over it), copied to `name`.
    int saves = 0;
    const auto save_as = [&](const std::string& name) {
        const ino_t before = inode_of(save);
        xdo("key ctrl+s");
        EXPECT_TRUE(wait_for([&] { return inode_of(save) != before && inode_of(save) != 0; }))
            << "Ctrl+S wrote no model; stderr: " << test::bytes_of(dir / "stderr.txt");
        ++saves;
        fs::copy_file(save, dir / name, fs::copy_options::overwrite_existing);
        return load_saved(dir / name);
    };

    (void)save_as("start.tdx");
    kScreen = framing_screen(renderer::Screen::desktop_monitor(),
                             compute::load_tdx((dir / "start.tdx").string(), model_memory_budget_bytes()).model.lattice.bounds(),
                             kEye, static_cast<double>(kW) / kH);
    move_to(kFrom);  // the tool rests on the surface under the cursor
    const Saved before = save_as("before.tdx");
    ASSERT_TRUE(std::isfinite(ray_depth(before, kFrom)));

    // The drag: left button down, the cursor across in steps, held at the end until the saved model shows the
    // groove reaching there (the tool glides behind the cursor), then released.
    xdo("mousedown 1");
    // Held still until the tool has pressed in where the drag starts.
    ASSERT_TRUE(wait_for([&] {
        const Saved pressed = save_as("pressed.tdx");
        return ray_depth(pressed, kFrom) - ray_depth(before, kFrom) > 0.003;
    })) << "the held left button never pressed the tool in";
    for (int i = 1; i <= 20; ++i) move_to(kFrom + (i / 20.0) * (kTo - kFrom));
    const Vec3 near_end = kFrom + 0.8 * (kTo - kFrom);
    Saved carved;
    const bool reached = wait_for([&] {
        carved = save_as("carved.tdx");
        return ray_depth(carved, near_end) - ray_depth(before, near_end) > 0.002;
    });
    xdo("mouseup 1");
    ASSERT_TRUE(reached) << "the groove never reached the end of the drag";
    int off_checked = 0;
    for (double u = 0.15; u <= 0.85; u += 0.1) {
        const Vec3 p = kFrom + u * (kTo - kFrom);
        const double d0 = ray_depth(before, p), d1 = ray_depth(carved, p);
        ASSERT_TRUE(std::isfinite(d0) && std::isfinite(d1)) << u;
        EXPECT_GT(d1 - d0, 0.002) << "no groove under the cursor at u = " << u;
        // 20 mm below the path (on the screen) the surface did not change.
        const double off_px = 0.02 / kScreen.height() * kH;
        const double off0 = ray_depth(before, p, off_px), off1 = ray_depth(carved, p, off_px);
        if (!std::isfinite(off0) || !std::isfinite(off1)) continue;  // past the bunny's outline
        ++off_checked;
        EXPECT_LT(std::abs(off1 - off0), 5e-4) << "carved away from the cursor path at u = " << u;
    }
    EXPECT_GE(off_checked, 3);
    EXPECT_LT(carved.volume_m3, before.volume_m3);

    // Ctrl+Z takes the groove back: the model's volume is the one before the drag, to the bit.
    xdo("key ctrl+z");
    Saved undone;
    EXPECT_TRUE(wait_for([&] {
        undone = save_as("undone.tdx");
        return undone.volume_m3 == before.volume_m3;
    })) << "Ctrl+Z did not restore the model";

    // The right button is the stylus button: a right drag moves the workspace (Peng's moving).
    move_to(kFrom);
    xdo("mousedown 3");
    for (int i = 1; i <= 10; ++i) move_to(kFrom + (i / 10.0) * Vec3(0.0, 0.03, 0.0));
    // Held until the loop has seen the button (a save is written after the events before it were handled).
    (void)save_as("moving.tdx");
    xdo("mouseup 3");
    (void)save_as("moved.tdx");

    // The middle button opens the pie menu at the tool; the cursor points at the slices: straight up past the ring
    // (Operation's ring opens there), then up and to the right (Union), released.
    move_to(kFrom);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    xdo("mousedown 2");
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    xdo("mousemove_relative -- 0 -130");
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    xdo("mousemove_relative -- 40 -60");
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    xdo("mouseup 2");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));

    // Esc closes the window; the report is written.
    xdo("key Escape");
    ASSERT_TRUE(wait_for([&] { return !app.running(); })) << "Esc did not close the window";
    EXPECT_EQ(app.exit_code(), 0) << test::bytes_of(dir / "stderr.txt");
    const nlohmann::json rep = test::read_json(out / "report.json");
    EXPECT_EQ(rep["display"], "window");
    EXPECT_EQ(rep["notes"][0], "ended: the session was ended (session.end)");
    EXPECT_EQ(rep["history"]["undos"], 1);
    EXPECT_EQ(rep["saves"]["count"].get<int>(), saves);
    EXPECT_GE(rep["haptics"]["button_presses"].get<int>(), 1);
    EXPECT_GT(rep["haptics"]["modelling_paused_ticks"].get<int>(), 0);
    EXPECT_GT(rep["mouse"]["workspace_moved_m"].get<double>(), 0.005) << rep["mouse"].dump();
    EXPECT_GT(rep["mouse"]["latency_ms"]["count"].get<int>(), 0);
    EXPECT_EQ(rep["controls"]["menu"]["choices"]["op.union"], 1) << rep["controls"].dump();
    EXPECT_EQ(rep["mouse"]["op"], "union") << rep["mouse"].dump();
    std::printf("[mouse xvfb] saves %d, cursor-to-tool latency median %.1f ms, p99 %.1f ms, workspace moved %.1f mm\n",
                saves, rep["mouse"]["latency_ms"]["median"].get<double>(), rep["mouse"]["latency_ms"]["p99"].get<double>(),
                1e3 * rep["mouse"]["workspace_moved_m"].get<double>());
    if (!HasFailure()) fs::remove_all(dir);  // kept for a look when something failed
}

// The M key turns symmetry on (a mirror across x, the session having none): a drag on the right half carves the left
// half too, at the mirror image of the path about the workpiece's centre, in the same stroke (one undo takes both).
TEST(MouseXvfb, TheMKeyMirrorsADragAcrossTheWorkpiecesCentre) {
    if (!have_binary("Xvfb") || !have_binary("xdotool"))
        GTEST_SKIP() << "needs the Xvfb and xdotool binaries (scripts/install-deps.sh installs xvfb and xdotool)";
    renderer::test::VirtualDisplay display(800, 600);
    const fs::path dir = test::temp_dir("mouse_xvfb_symmetry");
    const fs::path out = dir / "out", save = dir / "live.tdx";
    test::TridexProcess app(TRIDEX_EXE, mouse_run_args(dir, out, save), dir);
    const std::string w = test::find_window("tridex run");
    ASSERT_FALSE(w.empty());
    const auto move_to = [&](const Vec3& p) {
        const auto [x, y] = pixel_of(p);
        xdo("mousemove --window " + w + " " + std::to_string(x) + " " + std::to_string(y));
    };
    const auto save_as = [&](const std::string& name) {
        const ino_t before = inode_of(save);
        xdo("key ctrl+s");
        EXPECT_TRUE(wait_for([&] { return inode_of(save) != before && inode_of(save) != 0; }));
        fs::copy_file(save, dir / name, fs::copy_options::overwrite_existing);
        return load_saved(dir / name);
    };
    (void)save_as("start.tdx");
    const compute::Lattice lattice = compute::load_tdx((dir / "start.tdx").string(), model_memory_budget_bytes()).model.lattice;
    kScreen = framing_screen(renderer::Screen::desktop_monitor(), lattice.bounds(), kEye, static_cast<double>(kW) / kH);
    const double cx = 0.5 * (lattice.bounds().lo.x + lattice.bounds().hi.x);
    const Vec3 from(cx + 0.012, 0.0, 0.05), to(cx + 0.03, 0.0, 0.05);
    const auto mirror = [&](const Vec3& p) { return Vec3(2.0 * cx - p.x, p.y, p.z); };
    xdo("key m");
    move_to(from);
    const Saved before = save_as("before.tdx");
    xdo("mousedown 1");
    ASSERT_TRUE(wait_for([&] { return ray_depth(save_as("pressed.tdx"), from) - ray_depth(before, from) > 0.003; }));
    for (int i = 1; i <= 12; ++i) move_to(from + (i / 12.0) * (to - from));
    const Vec3 mid = 0.5 * (from + to);
    Saved carved;
    const bool reached = wait_for([&] {
        carved = save_as("carved.tdx");
        return ray_depth(carved, mirror(mid)) - ray_depth(before, mirror(mid)) > 0.002;
    });
    // Released and Ctrl+Z at once, as a quick hand does: the window hands the key's undo to the sculpt thread at once
    // and the button to the haptic loop with the frame, so the undo can arrive while the tool still cuts; it waits for
    // the release and takes back the whole drag.
    xdo("mouseup 1 key ctrl+z");
    ASSERT_TRUE(reached) << "no mirrored groove at the mirror image of the drag";
    EXPECT_GT(ray_depth(carved, mid) - ray_depth(before, mid), 0.002);
    // One undo takes the drag back with its mirrored copy: the press and the drag are one stroke (the held button).
    Saved undone;
    EXPECT_TRUE(wait_for([&] {
        undone = save_as("undone.tdx");
        return ray_depth(undone, mid) == ray_depth(before, mid) &&
               ray_depth(undone, mirror(mid)) == ray_depth(before, mirror(mid));
    }));
    xdo("key Escape");
    ASSERT_TRUE(wait_for([&] { return !app.running(); })) << "Esc did not close the window";
    EXPECT_EQ(app.exit_code(), 0) << test::bytes_of(dir / "stderr.txt");
    const nlohmann::json rep = test::read_json(out / "report.json");
    EXPECT_EQ(rep["controls"]["actions"]["symmetry.toggle"]["key"], 1) << rep["controls"].dump();
    EXPECT_EQ(rep["history"]["undos"], 1);
    EXPECT_EQ(rep["history"]["strokes"], 1) << rep["history"].dump();
    EXPECT_EQ(undone.volume_m3, before.volume_m3);
    std::printf("[mouse xvfb] undo requests that waited for the release: %d\n",
                rep["history"]["held_requests"].get<int>());
    if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
