// Undo, redo and saving in whole sessions, as a person uses them: keys (a window's, or a scene's scripted keys
// through the same handler) undo and redo strokes and save the model; the journal's marks and checkpoints let
// `tridex recover` rebuild exactly that model; a journal that fills its disk stops with one line while the session
// goes on, and every other output is still written.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "../test_paths.hpp"
#include "app/input/key_script.hpp"
#include "app/input/run_input.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/model/tdx_file.hpp"
#include "core/error.hpp"
#include "run_test_scene.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using renderer::InputAction;
using renderer::InputEvent;
using renderer::InputType;
using renderer::Key;

InputEvent key(Key k, std::uint8_t mods, InputAction a = InputAction::kPress) {
    InputEvent e;
    e.type = InputType::kKey;
    e.key = k;
    e.modifiers = mods;
    e.action = a;
    return e;
}

TEST(UndoKeys, CtrlZUndoesCtrlShiftZAndCtrlYRedoCtrlSSavesAndPlainLettersStillMove) {
    renderer::KeyboardMouseHead head(Pose{});
    renderer::SceneNavigation nav;
    RunInput in(&head, nav, renderer::MouseNavigation{});
    using renderer::modifier::kControl;
    using renderer::modifier::kShift;
    in.handle(key(Key::kZ, kControl));
    in.handle(key(Key::kZ, kControl, InputAction::kRepeat));  // held: stroke after stroke
    in.handle(key(Key::kZ, kControl, InputAction::kRelease));
    in.handle(key(Key::kZ, kControl | kShift));
    in.handle(key(Key::kY, kControl));
    in.handle(key(Key::kS, kControl));
    in.handle(key(Key::kS, kControl, InputAction::kRepeat));  // a held Ctrl+S saves once
    in.handle(key(Key::kZ, 0));                               // plain Z: nothing
    const std::vector<std::string> got = in.take_actions();
    const std::vector<std::string> want = {"edit.undo", "edit.undo", "edit.redo", "edit.redo", "file.save"};
    EXPECT_EQ(got, want);
    EXPECT_TRUE(in.take_actions().empty());
    // Ctrl+S did not walk the head back; a plain S does.
    const Vec3 before = head.head_at(1.0).position;
    in.handle(key(Key::kS, 0));
    EXPECT_NE(head.head_at(2.0).position, before);
}

TEST(UndoKeys, ChordsParseByNameAndUnknownPartsAreNamed) {
    const KeyChord c = parse_key_chord("Ctrl+Shift+Z", "k");
    EXPECT_EQ(c.key, Key::kZ);
    EXPECT_EQ(c.modifiers, renderer::modifier::kControl | renderer::modifier::kShift);
    EXPECT_EQ(parse_key_chord("esc", "k").key, Key::kEscape);
    EXPECT_EQ(parse_key_chord("tab", "k").key, Key::kTab);
    EXPECT_EQ(parse_key_chord("f1", "k").key, Key::kF1);
    try {
        parse_key_chord("ctrl+hyper+z", "scene.json: field 'keys[0].press'");
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "scene.json: field 'keys[0].press': unknown modifier 'hyper' in 'ctrl+hyper+z' (ctrl, shift, alt, super)");
    }
    EXPECT_THROW(parse_key_chord("ctrl+", "k"), Error);
    EXPECT_THROW(parse_key_chord("", "k"), Error);
}

using test::write_two_pass_scene;

TEST(UndoSession, ScriptedKeysUndoRedoAndSaveAndRecoverRebuildsThatModel) {
    const fs::path dir = test::temp_dir("undo_session");
    // After both passes: undo both strokes, redo one, save.
    const std::string scene = write_two_pass_scene(
        dir, R"([{"t_s": 3.2, "press": "ctrl+z"}, {"t_s": 3.25, "press": "ctrl+z"}, {"t_s": 3.3, "press": "ctrl+y"},
               {"t_s": 3.35, "press": "ctrl+s"}])");
    const test::ExeResult run = test::run_tridex(
        "run " + scene + " --display offscreen --cpu --seconds 5 --out " + (dir / "out").string(), dir / "log");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const nlohmann::json r = test::read_json(dir / "out" / "report.json");
    const nlohmann::json& h = r["history"];
    // The passes are strokes (the jump lifts the tool between them); the approach may touch the stock first.
    const int strokes = h["strokes"].get<int>();
    EXPECT_GE(strokes, 2) << h.dump();
    EXPECT_EQ(h["undos"], 2);
    EXPECT_EQ(h["redos"], 1);
    EXPECT_EQ(h["undo_steps"], strokes - 1);
    EXPECT_EQ(h["redo_steps"], 1);
    EXPECT_EQ(h["budget_bytes"], 256 << 20);
    EXPECT_GT(h["undo_ms"]["max"].get<double>(), 0.0);
    EXPECT_EQ(r["saves"]["count"], 1);
    EXPECT_EQ(r["saves"]["requests"], 1);     // Ctrl+S only
    EXPECT_EQ(r["key_requests_sent"], 4);     // two undos, a redo and the save
    // The saved model is the model after the keys: the first pass only.
    const compute::TdxModel saved = compute::load_tdx((dir / "out" / "model.tdx").string(), std::size_t{1} << 32);
    const double removed = r["volume_before_m3"].get<double>() - r["volume_after_m3"].get<double>();
    EXPECT_GT(removed, 0.0);

    // The journal holds the marks; recovering it gives the session's mesh byte for byte.
    const compute::Journal j = compute::read_journal((dir / "out" / "session.tdj").string());
    std::size_t undos = 0, redos = 0;
    for (const auto& rec : j.records) {
        undos += rec.kind == compute::JournalKind::kUndo;
        redos += rec.kind == compute::JournalKind::kRedo;
    }
    EXPECT_EQ(undos, 2u);
    EXPECT_EQ(redos, 1u);
    const test::ExeResult rec = test::run_tridex(
        "recover " + (dir / "out" / "session.tdj").string() + " --out " + (dir / "rec").string(), dir / "reclog");
    ASSERT_EQ(rec.exit_code, 0) << rec.err;
    EXPECT_TRUE(test::bytes_of(dir / "rec" / "sculpted.ply") == test::bytes_of(dir / "out" / "sculpted.ply"));
    const nlohmann::json rr = test::read_json(dir / "rec" / "report.json");
    EXPECT_EQ(rr["undos"], 2);
    EXPECT_EQ(rr["redos"], 1);
    EXPECT_NEAR(rr["volume_removed_m3"].get<double>(), removed, 1e-12);

    // Without the keys the session removes more: the second pass stays.
    const std::string plain = write_two_pass_scene(dir, "[]");
    const test::ExeResult run2 = test::run_tridex(
        "run " + plain + " --display offscreen --cpu --seconds 5 --out " + (dir / "plain").string(), dir / "log2");
    ASSERT_EQ(run2.exit_code, 0) << run2.err;
    const nlohmann::json p = test::read_json(dir / "plain" / "report.json");
    EXPECT_GT(p["volume_before_m3"].get<double>() - p["volume_after_m3"].get<double>(), 1.2 * removed);
    EXPECT_EQ(p["history"]["undo_steps"], p["history"]["strokes"]);
    fs::remove_all(dir);
}

TEST(UndoSession, RecoveryStartsFromTheNewestIntactCheckpointAndFallsBackToTheStart) {
    const fs::path dir = test::temp_dir("checkpoint_session");
    // Checkpoints every 0.2 s of wall time between strokes; an undo after the passes.
    const std::string scene = write_two_pass_scene(dir, R"([{"t_s": 3.2, "press": "ctrl+z"}])");
    const test::ExeResult run = test::run_tridex(
        "run " + scene + " --display offscreen --cpu --seconds 5 --checkpoint-s 0.2 --out " + (dir / "out").string(), dir / "log");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const nlohmann::json r = test::read_json(dir / "out" / "report.json");
    ASSERT_GE(r["journal"]["checkpoints"].get<int>(), 1) << r["journal"].dump();
    EXPECT_TRUE(r["journal"]["checkpoint_error"].is_null());
    const fs::path ckpt = dir / "out" / "session.tdj.checkpoint.tdx";
    ASSERT_TRUE(fs::exists(ckpt));

    const test::ExeResult rec = test::run_tridex(
        "recover " + (dir / "out" / "session.tdj").string() + " --out " + (dir / "rec").string(), dir / "reclog");
    ASSERT_EQ(rec.exit_code, 0) << rec.err;
    EXPECT_EQ(rec.err, "");
    const nlohmann::json rr = test::read_json(dir / "rec" / "report.json");
    EXPECT_NE(rr["replayed_from"].get<std::string>().find("checkpoint session.tdj.checkpoint.tdx"), std::string::npos)
        << rr["replayed_from"];
    EXPECT_TRUE(test::bytes_of(dir / "rec" / "sculpted.ply") == test::bytes_of(dir / "out" / "sculpted.ply"));

    // A damaged checkpoint is not trusted: one line says so and the whole journal is replayed, to the same mesh.
    {
        std::fstream f(ckpt, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(40);
        f.put('\x5a');
    }
    const test::ExeResult rec2 = test::run_tridex(
        "recover " + (dir / "out" / "session.tdj").string() + " --out " + (dir / "rec2").string(), dir / "reclog2");
    ASSERT_EQ(rec2.exit_code, 0) << rec2.err;
    EXPECT_NE(rec2.err.find("not used: "), std::string::npos) << rec2.err;
    EXPECT_NE(rec2.err.find("not the checkpoint the journal names"), std::string::npos) << rec2.err;
    EXPECT_EQ(test::read_json(dir / "rec2" / "report.json")["replayed_from"], "the start");
    EXPECT_TRUE(test::bytes_of(dir / "rec2" / "sculpted.ply") == test::bytes_of(dir / "out" / "sculpted.ply"));
    fs::remove_all(dir);
}

// A disk that fills during the session, played by a file-size limit (RLIMIT_FSIZE: writes past it fail with EFBIG,
// as they would with ENOSPC): the journal stops with one line, the session goes on to the end, Ctrl+S still saves
// (small), and every output that fits is written with the report saying what failed.
TEST(UndoSession, AJournalThatFillsTheDiskStopsWithOneLineAndTheSessionGoesOn) {
    const fs::path dir = test::temp_dir("full_session");
    const std::string scene = write_two_pass_scene(dir, R"([{"t_s": 3.3, "press": "ctrl+s"}])");
    const fs::path out = dir / "out";
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::signal(SIGXFSZ, SIG_IGN);
        const rlimit lim{120 * 1024, 120 * 1024};  // the journal outgrows it within the first second
        ::setrlimit(RLIMIT_FSIZE, &lim);
        const std::string cmd = std::string(TRIDEX_EXE) + " run " + scene + " --display offscreen --cpu --seconds 4 --out " +
                                out.string() + " > " + (dir / "stdout.txt").string() + " 2> " + (dir / "stderr.txt").string();
        ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    const std::string err = test::bytes_of(dir / "stderr.txt");
    EXPECT_NE(err.find("this session is no longer being saved: journal: write failed"), std::string::npos) << err;
    // The report is written whatever else failed, and says the journal stopped.
    const nlohmann::json r = test::read_json(out / "report.json");
    EXPECT_NE(r["journal"]["error"].get<std::string>().find("File too large"), std::string::npos);
    // The session went on to the end (4 s; the loop's tick count depends on the machine's load: missed deadlines
    // are skipped).
    EXPECT_GT(r["session_s"].get<double>(), 3.9) << "the session went on to the end";
    EXPECT_GT(r["haptics"]["ticks"].get<int>(), 2000) << "the haptic loop went on";
    EXPECT_EQ(r["saves"]["count"], 1) << r["saves"].dump();
    EXPECT_NO_THROW(compute::load_tdx((out / "model.tdx").string(), std::size_t{1} << 32));
    // Exit 0 when every final output fitted, else 2 with the failure named and the rest written.
    if (WEXITSTATUS(status) != 0) {
        EXPECT_EQ(WEXITSTATUS(status), 2);
        EXPECT_NE(err.find("the other outputs and report.json were written to"), std::string::npos) << err;
    }
    // The journal's valid prefix still recovers.
    const test::ExeResult rec = test::run_tridex("recover " + (out / "session.tdj").string() + " --out " + (dir / "rec").string(),
                                                 dir / "reclog");
    EXPECT_EQ(rec.exit_code, 0) << rec.err;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
