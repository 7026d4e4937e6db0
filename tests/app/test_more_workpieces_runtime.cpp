// A SessionRuntime of two workpieces, on its threads (the haptic loop, two sculpt threads, two journals): a simulated
// hand pressed into the second carves it alone, the first gets every tick in its frame and stays whole; an undo from
// the window's thread goes to the workpiece the tool carved and gives its volume back bit for bit; each journal
// replays to its own model; undo and redo follow one order across the workpieces. Run under ThreadSanitizer too (the `tsan` test set).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <thread>
#include <vector>

#include "app/scene/workpiece_list.hpp"
#include "app/support/assets.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "compute/journal/journal_reader.hpp"
#include "core/math.hpp"
#include <glm/gtc/quaternion.hpp>
#include "compute/journal/journal_replay.hpp"
#include "compute/model/volume.hpp"
#include "devices/device_profiles.hpp"
#include "devices/registry/device_registry.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

// The default device's home position, m.
Vec3 device_home() { return devices::home_position_m(devices::profile_by_name(SessionSpec{}.device)); }

// Two bunnies at resolution 32, 20 cm apart (the second turned by `second_turn`), a 6 mm ball, and the device's
// home on the second bunny's centre.
SessionSpec two_bunnies(const Quat& second_turn) {
    SessionSpec s;
    s.mesh_path = default_mesh_path();
    s.resolution = 32;
    s.stock_m = 0.1;
    s.workpiece_centre_m = Vec3(-0.1, 0.0, 0.05);
    WorkpieceSpec second = workpiece_at(s, 0);
    second.centre_m = Vec3(0.1, 0.0, 0.05);
    second.turn = second_turn;
    s.more_workpieces = {second};
    s.workspace_mode = "scaling";
    s.tool = ToolShape{ToolKind::kBall, 0.006, 0.0, 0};
    s.device_origin_m = Vec3(0.1, 0.0, 0.05) - device_home();
    validate_spec(s, "test");
    return s;
}

TEST(MoreWorkpiecesRuntime, TheTouchedSecondIsCarvedAloneAndItsUndoAndJournalAreItsOwn) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-more-workpieces-runtime";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const Vec3 home = device_home();
    SessionSpec s = two_bunnies(glm::angleAxis(glm::radians(90.0), Vec3(0.0, 1.0, 0.0)));
    Workpiece wp = prepare_session_workpiece(s);
    std::vector<Workpiece> more = prepare_more_workpieces(s);
    const double first_before = wp.volume_dexel_m3, second_before = more[0].volume_dexel_m3;
    // The hand from 8 cm in front of the second bunny's centre to 3 cm in front of it and back out (one stroke that
    // closes once the tool has idled in the air for SculptThread::kStrokeIdleS), then held out there.
    devices::DeviceInputs in;
    in.period_s = s.period_s;
    in.hand_path.emplace(std::vector<double>{0.0, 0.3, 1.0, 1.7, 60.0},
                         std::vector<Vec3>{home + Vec3(0.0, 0.0, 0.08), home + Vec3(0.0, 0.0, 0.08),
                                           home + Vec3(0.0, 0.0, 0.03), home + Vec3(0.0, 0.0, 0.08),
                                           home + Vec3(0.0, 0.0, 0.08)});
    RuntimeOptions ro;
    ro.sculpt.cpu = true;
    ro.sculpt.journal = (dir / "session.tdj").string();
    ro.publish_meshes = true;  // the further workpiece hands whole meshes over, as in a run
    ro.loop.free_run = true;   // surfaces as fresh as in a session that keeps up, however loaded the machine
    SessionRuntime rt(s, std::move(wp), std::move(more), make_device(s, in), home + s.device_origin_m, ro);
    ASSERT_EQ(rt.workpiece_count(), 2u);
    rt.start();
    const auto wait_device_s = [&](double t) {
        while (rt.latest_view().t_s < t) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    };
    // This thread reads the further workpiece's meshes while it is carved, as the render thread does.
    std::uint64_t versions = 0;
    while (rt.latest_view().t_s < 2.6) {
        versions = std::max(versions, rt.more_workpiece(1).latest_mesh().version);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_EQ(rt.latest_view().target_workpiece, 1);  // the nearest, the hand being nearer it
    ASSERT_TRUE(rt.request(SculptRequest::kUndo));  // the stroke closed when the hand held still in the air
    wait_device_s(3.2);
    rt.stop();
    EXPECT_GT(versions, 1u);
    EXPECT_EQ(compute::dexel_volume_m3(rt.workpiece().model), first_before);
    const SculptStats& st = rt.more_workpiece(1).sculpt_stats();
    EXPECT_GT(st.booleans, 0u);
    EXPECT_EQ(st.history.undos, 1u);
    EXPECT_EQ(compute::dexel_volume_m3(rt.more_workpiece(1).workpiece().model), second_before);  // given back whole
    EXPECT_EQ(rt.sculpt_stats().history.undos, 0u);
    EXPECT_EQ(rt.more_workpiece(1).sculpt_stats().samples, rt.sculpt_stats().samples);  // every tick reached both
    // Each journal is its own workpiece's: the second's replays, undo included, to the session's model.
    const compute::Journal j = compute::read_journal((dir / "session-wp2.tdj").string());
    SessionSpec one = spec_from_json(j.session, "journal");
    EXPECT_TRUE(one.more_workpieces.empty());
    EXPECT_EQ(one.workpiece_centre_m, Vec3(0.1, 0.0, 0.05));
    Workpiece again = prepare_session_workpiece(one);
    const compute::JournalApplyStats applied = compute::journal_apply(again.model, j.records, replay_settings(one));
    EXPECT_EQ(applied.undos, 1u);
    EXPECT_EQ(compute::dexel_volume_m3(again.model), second_before);
}

// One undo order across the workpieces: the hand carves the second bunny, then the first. Two undos from the
// window's thread take back the first's stroke (the newest), then the second's, whichever the tool is near; a redo
// brings back the one undone last (the second's).
TEST(MoreWorkpiecesRuntime, UndoTakesBackTheNewestStrokeOfAllAndRedoTheLastUndone) {
    const fs::path dir = fs::temp_directory_path() / "tridex-test-more-workpieces-undo-order";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const Vec3 home = device_home();
    SessionSpec s = two_bunnies(Quat(1.0, 0.0, 0.0, 0.0));
    Workpiece wp = prepare_session_workpiece(s);
    std::vector<Workpiece> more = prepare_more_workpieces(s);
    const double first_before = wp.volume_dexel_m3, second_before = more[0].volume_dexel_m3;
    // Into the second bunny and out, over to the first (20 cm to the left), into it and out, then held in the air.
    devices::DeviceInputs in;
    in.period_s = s.period_s;
    const Vec3 left(-0.2, 0.0, 0.0);
    in.hand_path.emplace(std::vector<double>{0.0, 0.3, 1.0, 1.7, 2.4, 3.1, 3.8, 60.0},
                         std::vector<Vec3>{home + Vec3(0.0, 0.0, 0.08), home + Vec3(0.0, 0.0, 0.08),
                                           home + Vec3(0.0, 0.0, 0.03), home + Vec3(0.0, 0.0, 0.08),
                                           home + left + Vec3(0.0, 0.0, 0.08), home + left + Vec3(0.0, 0.0, 0.03),
                                           home + left + Vec3(0.0, 0.0, 0.08), home + left + Vec3(0.0, 0.0, 0.08)});
    RuntimeOptions ro;
    ro.sculpt.cpu = true;
    ro.sculpt.journal = (dir / "session.tdj").string();
    // The loop runs free, at most kFreeRunLead samples ahead of each sculpt thread: the contact then reads surfaces
    // as fresh as in a session whose sculpt threads keep up, however loaded the machine (a paced loop under
    // ThreadSanitizer beside other tests can run seconds ahead of them, and where the strokes land then differs).
    ro.loop.free_run = true;
    SessionRuntime rt(s, std::move(wp), std::move(more), make_device(s, in), home + s.device_origin_m, ro);
    rt.start();
    while (rt.latest_view().t_s < 4.6) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const haptics::LoopStats ls = rt.loop_stats();
    SCOPED_TRACE(::testing::Message() << "loop: " << ls.ticks << " ticks, " << ls.overruns << " overruns, "
                                      << ls.samples_dropped << " samples dropped, " << ls.watchdog_trips
                                      << " watchdog trips, " << ls.velocity_limit_ticks << " ticks over speed");
    EXPECT_EQ(rt.latest_view().target_workpiece, 0);  // the hand is at the first bunny now
    const SculptLive first_live = rt.sculpt_live(), second_live = rt.more_workpiece(1).sculpt_live();
    EXPECT_GT(first_live.undo_times.undo_at, second_live.undo_times.undo_at);  // both closed, the first's newer
    EXPECT_GE(second_live.undo_times.undo_at, 0);
    ASSERT_TRUE(rt.request(SculptRequest::kUndo));  // the first's stroke
    ASSERT_TRUE(rt.request(SculptRequest::kUndo));  // waits for the first to be taken, then the second's
    ASSERT_TRUE(rt.request(SculptRequest::kRedo));  // the second's again: undone last
    rt.stop();  // sends what still waits, in turn
    const SculptStats& a = rt.sculpt_stats();
    const SculptStats& b = rt.more_workpiece(1).sculpt_stats();
    EXPECT_EQ(a.history.strokes, 1u);
    EXPECT_EQ(b.history.strokes, 1u);
    EXPECT_EQ(a.history.undos, 1u);
    EXPECT_EQ(a.history.redos, 0u);
    EXPECT_EQ(b.history.undos, 1u);
    EXPECT_EQ(b.history.redos, 1u);
    EXPECT_EQ(compute::dexel_volume_m3(rt.workpiece().model), first_before);  // undone
    EXPECT_LT(compute::dexel_volume_m3(rt.more_workpiece(1).workpiece().model), second_before);  // redone
}

}  // namespace
}  // namespace tridex::app
