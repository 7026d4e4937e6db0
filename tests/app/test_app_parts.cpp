// Unit tests of the app's own logic: order statistics, the stroke planned on a model, session settings.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/support/output_dir.hpp"
#include "app/session/view/framing.hpp"
#include "app/session/batch/session.hpp"
#include "app/scene/session_spec.hpp"
#include "core/summary.hpp"
#include "app/scene/stroke.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

namespace tridex::app {
namespace {

TEST(Summarize, NearestRankPercentiles) {
    std::vector<double> v;
    for (int i = 100; i >= 1; --i) v.push_back(i);  // 1..100, unsorted
    const Summary s = summarize(v);
    EXPECT_EQ(s.median, 50.0);
    EXPECT_EQ(s.p99, 99.0);
    EXPECT_EQ(s.max, 100.0);
    EXPECT_DOUBLE_EQ(s.mean, 50.5);
    const Summary e = summarize({});
    EXPECT_EQ(e.max, 0.0);
}

// A 0.2 x 0.1 x 0.1 m box with its +z face at z = 0.05 and its +y face at y = 0.05.
compute::TriDexel box_model() {
    const Aabb box{Vec3(-0.1, -0.05, -0.05), Vec3(0.1, 0.05, 0.05)};
    compute::TriDexel m = compute::TriDexel::empty(compute::Lattice::around(box, 64), std::size_t(1) << 30);
    compute::scan_convert(box_mesh(box), m);
    return m;
}

// A run killed while writing leaves "<name>.tmp-<pid>" behind; the next run in that folder removes those of
// processes that are gone, and keeps its own and other files.
TEST(OutputDir, TemporaryFilesOfDeadWritersAreRemovedAtTheNextStart) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("tridex_stale_tmp_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto touch = [&](const std::string& name) { std::ofstream(dir / name) << "x"; };
    touch("report.json.tmp-999999999");  // no process can have this PID (the kernel's limit is 4194304)
    touch("model.tdx.tmp-999999998");
    touch("left.png.tmp-" + std::to_string(::getpid()));  // this process: a write in progress
    touch("notes.tmp-abc");                                // not a PID
    touch("report.json");
    prepare_output_dir(dir.string(), "--out");
    EXPECT_FALSE(fs::exists(dir / "report.json.tmp-999999999"));
    EXPECT_FALSE(fs::exists(dir / "model.tdx.tmp-999999998"));
    EXPECT_TRUE(fs::exists(dir / ("left.png.tmp-" + std::to_string(::getpid()))));
    EXPECT_TRUE(fs::exists(dir / "notes.tmp-abc"));
    EXPECT_TRUE(fs::exists(dir / "report.json"));
    touch("again.tmp-999999997");
    EXPECT_EQ(remove_stale_temp_files(dir.string()), 1u);
    EXPECT_EQ(remove_stale_temp_files((dir / "none").string()), 0u);  // a missing folder: nothing, no throw
    fs::remove_all(dir);
}

TEST(PlanStroke, FollowsTheFacingSideAtTheRequestedDepth) {
    const compute::TriDexel m = box_model();
    for (int axis : {1, 2}) {
        StrokeParams p;
        p.press_axis = axis;
        p.duration_s = 4.0;
        p.length_m = 0.1;
        p.tool_radius_m = 0.008;
        p.depth_m = 0.006;
        const StrokePlan plan = plan_stroke(m, p);
        ASSERT_EQ(plan.t_s.size(), plan.world_m.size());
        EXPECT_EQ(plan.t_s.front(), 0.0);
        EXPECT_EQ(plan.t_s.back(), 4.0);
        for (std::size_t i = 1; i < plan.t_s.size(); ++i) EXPECT_GT(plan.t_s[i], plan.t_s[i - 1]);
        // While carving, the ball centre is radius - depth above the flat face (0.05 m), within float depth rounding.
        int carving = 0;
        for (std::size_t i = 0; i < plan.t_s.size(); ++i) {
            if (plan.t_s[i] < 0.3 * 4.0 - 1e-9 || plan.t_s[i] > 0.85 * 4.0 + 1e-9) continue;
            EXPECT_NEAR(plan.world_m[i][axis], 0.05 + 0.002, 1e-6) << "axis " << axis << " waypoint " << i;
            ++carving;
        }
        EXPECT_GE(carving, 10);
        EXPECT_NEAR(plan.world_m.front()[axis], 0.05 + p.clearance_m, 1e-6);  // starts clear of the surface
        EXPECT_NEAR(plan.world_m.back().x - plan.world_m.front().x, 0.1, 1e-9);  // the pass length
    }
}

TEST(PlanStroke, AStartDelayHoldsTheHandLiftedThenShiftsTheWholeStroke) {
    const compute::TriDexel m = box_model();
    StrokeParams p;
    p.duration_s = 4.0;
    p.length_m = 0.1;
    const StrokePlan now = plan_stroke(m, p);
    p.start_s = 2.5;
    EXPECT_DOUBLE_EQ(p.end_s(), 6.5);
    const StrokePlan later = plan_stroke(m, p);
    ASSERT_EQ(later.t_s.size(), now.t_s.size() + 1);
    EXPECT_EQ(later.t_s.front(), 0.0);
    EXPECT_EQ(later.world_m.front(), now.world_m.front());  // waiting where the stroke begins, lifted
    for (std::size_t i = 0; i < now.t_s.size(); ++i) {
        EXPECT_DOUBLE_EQ(later.t_s[i + 1], now.t_s[i] + 2.5);
        EXPECT_EQ(later.world_m[i + 1], now.world_m[i]);
    }
    EXPECT_DOUBLE_EQ(later.t_s.back(), 6.5);
    for (const double bad : {-1.0, std::nan("")}) {
        p.start_s = bad;
        try {
            (void)plan_stroke(m, p);
            ADD_FAILURE() << "start_s " << bad << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("stroke.start_s"), std::string::npos) << e.what();
        }
    }
}

TEST(PlanStroke, RefusesAnEmptyModelAndABadAxis) {
    const compute::TriDexel empty =
        compute::TriDexel::empty(compute::Lattice::around(Aabb{Vec3(0.0), Vec3(0.1)}, 32), std::size_t(1) << 30);
    EXPECT_THROW(plan_stroke(empty, StrokeParams{}), Error);
    StrokeParams bad;
    bad.press_axis = 0;
    EXPECT_THROW(plan_stroke(box_model(), bad), Error);
}

}  // namespace
}  // namespace tridex::app

namespace tridex::app {
namespace {

TEST(SessionSpec, ElasticObjectsRoundTripThroughTheRecordingHeaderAndReachTheLoop) {
    SessionSpec s;
    haptics::ElasticSphere e;
    e.centre_m = Vec3(0.01, -0.02, 0.3);
    e.radius_m = 0.025;
    e.stiffness_n_per_m = 250.0;
    e.influence_m = 0.01;
    s.elastic_objects = {e, e};
    s.elastic_objects[1].radius_m = 0.05;
    const SessionSpec back = spec_from_json(spec_to_json(s), "test");
    ASSERT_EQ(back.elastic_objects.size(), 2u);
    EXPECT_EQ(back.elastic_objects[0].centre_m, e.centre_m);
    EXPECT_EQ(back.elastic_objects[1].radius_m, 0.05);
    EXPECT_EQ(back.elastic_objects[0].stiffness_n_per_m, 250.0);
    EXPECT_EQ(back.elastic_objects[0].influence_m, 0.01);
    EXPECT_EQ(loop_config(back, 10).elastic_objects.size(), 2u);
    // Sessions without them write no field and read none; a bad one is refused naming it.
    EXPECT_FALSE(nlohmann::json::parse(spec_to_json(SessionSpec{})).contains("elastic_objects"));
    nlohmann::json bad = nlohmann::json::parse(spec_to_json(s));
    bad["elastic_objects"][1]["influence_radius_m"] = 1.0;
    try {
        spec_from_json(bad.dump(), "rec.trdx");
        FAIL() << "an influence radius larger than the sphere was accepted";
    } catch (const Error& x) {
        EXPECT_NE(std::string(x.what()).find("rec.trdx: settings field 'elastic_objects[1]'"), std::string::npos) << x.what();
    }
}

TEST(SessionSpec, KeepIslandsRoundTripsAndOlderRecordingsReadAsKeepingEveryPiece) {
    SessionSpec s;
    EXPECT_FALSE(s.keep_islands);  // sessions remove specks unless told
    EXPECT_FALSE(spec_from_json(spec_to_json(s), "test").keep_islands);
    s.keep_islands = true;
    EXPECT_TRUE(spec_from_json(spec_to_json(s), "test").keep_islands);
    // A recording or journal from before speck removal: its session kept every piece, and so does its replay.
    nlohmann::json old = nlohmann::json::parse(spec_to_json(SessionSpec{}));
    old.erase("keep_islands");
    EXPECT_TRUE(spec_from_json(old.dump(), "old").keep_islands);
    old["keep_islands"] = "yes";
    EXPECT_THROW(spec_from_json(old.dump(), "bad"), Error);
}

TEST(SessionSpec, ClayGroupSizeRoundTripsOlderRecordingsReadAs16AndReachesTheReplay) {
    SessionSpec s;
    EXPECT_EQ(s.clay_group_sweeps, compute::kClayGroupSweeps);
    EXPECT_EQ(spec_from_json(spec_to_json(s), "test").clay_group_sweeps, compute::kClayGroupSweeps);
    s.clay_group_sweeps = 7;
    EXPECT_EQ(spec_from_json(spec_to_json(s), "test").clay_group_sweeps, 7u);
    s.keep_islands = true;
    const compute::JournalApplyFrom r = replay_settings(s);
    EXPECT_EQ(r.clay_group_sweeps, 7u);
    EXPECT_FALSE(r.remove_islands);
    EXPECT_EQ(r.history_budget_bytes, s.history_budget_bytes);
    // A recording or journal from before the size was recorded: its session grouped 16 sweeps, and so does its replay.
    nlohmann::json old = nlohmann::json::parse(spec_to_json(SessionSpec{}));
    old.erase("clay_group_sweeps");
    EXPECT_EQ(spec_from_json(old.dump(), "old").clay_group_sweeps, 16u);
    old["clay_group_sweeps"] = "many";
    EXPECT_THROW(spec_from_json(old.dump(), "bad"), Error);
    // Out of range: validate_spec names the field.
    for (const std::size_t n : {std::size_t{0}, compute::kClayGroupSweepsMax + 1}) {
        SessionSpec bad;
        bad.clay_group_sweeps = n;
        try {
            validate_spec(bad, "rec.trdx");
            ADD_FAILURE() << "clay group size " << n << " was accepted";
        } catch (const Error& x) {
            EXPECT_NE(std::string(x.what()).find("rec.trdx: settings field 'clay_group_sweeps'"), std::string::npos)
                << x.what();
        }
    }
}

TEST(SessionSpec, OpAndMaterialRoundTripThroughTheRecordingHeaderAndReachTheLoop) {
    SessionSpec s;
    s.op = "paint";
    s.material = 5;
    const SessionSpec back = spec_from_json(spec_to_json(s), "test");
    EXPECT_EQ(back.op, "paint");
    EXPECT_EQ(back.material, 5);
    const haptics::HapticLoopConfig cfg = loop_config(back, 10);
    EXPECT_EQ(cfg.op, ToolOp::kPaint);
    EXPECT_EQ(cfg.material, 5);
    EXPECT_FALSE(cfg.contact.cutting);  // painting removes nothing, so nothing resists the advance
    EXPECT_TRUE(loop_config(SessionSpec{}, 10).contact.cutting);
    // A recording made before op/material existed still loads, as a subtract session.
    nlohmann::json old = nlohmann::json::parse(spec_to_json(SessionSpec{}));
    old.erase("op");
    old.erase("material");
    EXPECT_EQ(spec_from_json(old.dump(), "old").op, "subtract");
    s.op = "drill";
    EXPECT_THROW(loop_config(s, 10), Error);
    s.op = "union";
    s.material = 0;
    try {
        loop_config(s, 10);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--material"), std::string::npos) << e.what();
    }
}

TEST(SessionSpec, SymmetryRoundTripsThroughTheRecordingHeaderAndReachesTheLoop) {
    SessionSpec s;
    s.symmetry = "radial:6:y";
    const SessionSpec back = spec_from_json(spec_to_json(s), "test");
    EXPECT_EQ(back.symmetry, "radial:6:y");
    EXPECT_EQ(loop_config(back, 10).symmetry, (Symmetry{0, 1, 6}));
    EXPECT_FALSE(loop_config(SessionSpec{}, 10).symmetry.on());
    // A recording made before symmetry existed still loads, as a session without it.
    nlohmann::json old = nlohmann::json::parse(spec_to_json(SessionSpec{}));
    old.erase("symmetry");
    EXPECT_EQ(spec_from_json(old.dump(), "old").symmetry, "off");
    s.symmetry = "xx";
    try {
        loop_config(s, 10);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--symmetry: bad symmetry 'xx'"), std::string::npos) << e.what();
    }
}

// The demo's images look through the part of the wall around the workpiece: every corner of the box, seen from the
// head, lands inside the crop, the crop has the image's aspect and lies in the wall's plane, and a degenerate input
// keeps the whole wall.
TEST(Framing, TheCropHoldsTheWorkpieceAsSeenFromTheHeadInTheImagesAspect) {
    const renderer::Screen wall = renderer::Screen::powerwall();
    const Aabb box{Vec3(-0.15, -0.12, 0.15), Vec3(0.15, 0.12, 0.45)};
    const Vec3 head(0.0, 0.15, 0.65);
    const renderer::Screen s = framing_screen(wall, box, head, 4.0 / 3.0);
    EXPECT_NEAR(s.width() / s.height(), 4.0 / 3.0, 1e-12);
    EXPECT_LT(s.width(), 0.5 * wall.width());
    EXPECT_NEAR(s.lower_left.z, 0.0, 1e-12);
    EXPECT_NEAR(s.upper_left.z, 0.0, 1e-12);
    double umin = 1e9, umax = -1e9;
    for (int k = 0; k < 8; ++k) {
        const Vec3 c((k & 1) ? box.hi.x : box.lo.x, (k & 2) ? box.hi.y : box.lo.y, (k & 4) ? box.hi.z : box.lo.z);
        const Vec3 p = head + (c - head) * (head.z / (head.z - c.z));  // onto z = 0
        EXPECT_GT(p.x, s.lower_left.x);
        EXPECT_LT(p.x, s.lower_right.x);
        EXPECT_GT(p.y, s.lower_left.y);
        EXPECT_LT(p.y, s.upper_left.y);
        umin = std::min(umin, p.x), umax = std::max(umax, p.x);
    }
    // The margin is a tenth of the box's extent on each side (here the height decides, so check the width loosely).
    EXPECT_GT(s.width(), 1.2 * (umax - umin) - 1e-9);
    // Degenerate inputs: the whole wall.
    const renderer::Screen same = framing_screen(wall, Aabb{}, head, 4.0 / 3.0);
    EXPECT_EQ(same.lower_left, wall.lower_left);
    const renderer::Screen behind = framing_screen(wall, Aabb{Vec3(0.0, 0.0, 0.7), Vec3(0.1, 0.1, 0.8)}, head, 1.0);
    EXPECT_EQ(behind.upper_left, wall.upper_left);
}

}  // namespace
}  // namespace tridex::app
