// The model's coarseness changed in whole sessions, as a person changes it: Page Up and Page Down (a scene's scripted
// keys, through the window's handler) re-sample the model during the session, Ctrl+Z takes a change back; the journal
// and the recording rebuild the same model byte for byte, on the lattice the session ended on. (A live session's
// samples depend on its timing, through the haptic proxy, so two live sessions are compared through their own
// journals; compute_test_sculpt_thread_coarseness checks that an undone change gives back the old model bit for bit.)
#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "compute/model/tdx_file.hpp"
#include "compute/tools/model_resample.hpp"
#include "run_test_scene.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

// The resolution of the model `tridex recover` wrote into `dir`; its settings must name the same.
int recovered_resolution(const fs::path& dir) {
    const compute::TdxModel m = compute::load_tdx((dir / "model.tdx").string(), std::size_t{1} << 30);
    const int n = compute::lattice_resolution(m.model.lattice);
    EXPECT_EQ(nlohmann::json::parse(m.settings_json)["resolution"], n) << "the saved settings name another lattice";
    return n;
}

TEST(CoarsenessSession, PageUpAndDownResampleLiveAndRecoverAndReplayRebuildTheModel) {
    const fs::path dir = test::temp_dir("coarseness_session");
    // Finer before the passes (48 -> 96), coarser after them (96 -> 48), and that change taken back.
    const std::string scene = test::write_two_pass_scene(
        dir, R"([{"t_s": 0.05, "press": "pageup"}, {"t_s": 3.2, "press": "pagedown"}, {"t_s": 3.3, "press": "ctrl+z"}])");
    const fs::path rec = dir / "session.trdx";
    const test::ExeResult run = test::run_tridex("run " + scene + " --display offscreen --cpu --seconds 5 --record " +
                                                     rec.string() + " --out " + (dir / "out").string(),
                                                 dir / "log");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const nlohmann::json r = test::read_json(dir / "out" / "report.json");
    const nlohmann::json& changes = r["history"]["coarseness"];
    ASSERT_EQ(changes.size(), 2u) << r["history"].dump();
    EXPECT_EQ(changes[0]["resolution_before"], 48);
    EXPECT_EQ(changes[0]["resolution_after"], 96);
    EXPECT_EQ(changes[1]["resolution_after"], 48);
    EXPECT_NEAR(changes[0]["cell_after_m"].get<double>(), 0.5 * changes[0]["cell_before_m"].get<double>(), 1e-12);
    EXPECT_GE(r["history"]["undos"], 1);
    EXPECT_GE(r["history"]["redo_steps"], 1) << "the coarser change can be redone";
    const double removed = r["volume_before_m3"].get<double>() - r["volume_after_m3"].get<double>();
    EXPECT_GT(removed, 0.0) << "the passes cut on the finer lattice";

    // `tridex recover` of its journal, and `tridex replay` of its recording: the same mesh, byte for byte.
    const test::ExeResult recovered = test::run_tridex(
        "recover " + (dir / "out" / "session.tdj").string() + " --out " + (dir / "rec").string(), dir / "reclog");
    ASSERT_EQ(recovered.exit_code, 0) << recovered.err;
    const std::string live = test::bytes_of(dir / "out" / "sculpted.ply");
    ASSERT_GT(live.size(), 1000u);
    EXPECT_TRUE(test::bytes_of(dir / "rec" / "sculpted.ply") == live) << "recover built another model";
    EXPECT_EQ(recovered_resolution(dir / "rec"), 96) << "the coarser change was taken back";
    const test::ExeResult replayed = test::run_tridex(
        "replay " + rec.string() + " --cpu --width 96 --height 72 --out " + (dir / "replay").string(), dir / "replaylog");
    ASSERT_EQ(replayed.exit_code, 0) << replayed.err;
    EXPECT_TRUE(test::bytes_of(dir / "replay" / "sculpted.ply") == live) << "the replay built another model";
    EXPECT_EQ(test::read_json(dir / "replay" / "report.json")["history"]["coarseness"].size(), 2u);

    // A change taken back at once: the passes cut the old lattice, and the change can be redone.
    const std::string undone = test::write_two_pass_scene(
        dir, R"([{"t_s": 0.05, "press": "pageup"}, {"t_s": 0.1, "press": "ctrl+z"}])");
    ASSERT_EQ(test::run_tridex("run " + undone + " --display offscreen --cpu --seconds 5 --out " +
                                   (dir / "undone").string(), dir / "log2").exit_code, 0);
    const nlohmann::json u = test::read_json(dir / "undone" / "report.json");
    EXPECT_EQ(u["history"]["coarseness"].size(), 1u);
    ASSERT_EQ(test::run_tridex("recover " + (dir / "undone" / "session.tdj").string() + " --out " +
                                   (dir / "undone_rec").string(), dir / "reclog2").exit_code, 0);
    EXPECT_EQ(recovered_resolution(dir / "undone_rec"), 48);
    EXPECT_TRUE(test::bytes_of(dir / "undone_rec" / "sculpted.ply") == test::bytes_of(dir / "undone" / "sculpted.ply"));
    if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
