// Sessions save their final model (--save) and start from a saved model (--workpiece, scene workpiece.model); a
// recording of such a session replays from the same model, and refuses a model file that changed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "test_files.hpp"
#include "app/commands/demo/demo.hpp"
#include "app/commands/replay/replay.hpp"
#include "app/scene/run_scene.hpp"
#include "app/session/run/run_session.hpp"
#include "app/session/batch/session.hpp"
#include "app/scene/session_spec.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"
#include "run_test_scene.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

DemoOptions small_demo(const fs::path& dir, const std::string& name) {
    DemoOptions d;
    d.resolution = 32;
    d.seconds = 0.5;
    d.width = d.height = 32;
    d.out = (dir / name).string();
    d.cpu = true;
    return d;
}

std::string replay_error(const std::string& recording, const fs::path& out) {
    OutputOptions o;
    o.out = out.string();
    o.width = o.height = 32;
    try {
        run_replay(recording, o, SculptOptions{true, false, false, false, ""});
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(ModelSessions, SaveStartFromTheModelAndReplayFromIt) {
    const fs::path dir = test::temp_dir("model_sessions");
    // 1. A session from the mesh saves its final model, with the session's settings.
    DemoOptions first = small_demo(dir, "first");
    first.save = (dir / "first.tdx").string();
    run_demo(first);
    const compute::TdxModel saved = compute::load_tdx(first.save, std::size_t{1} << 30);
    const SessionSpec spec = spec_from_json(saved.settings_json, first.save);
    EXPECT_EQ(spec.resolution, 32);
    EXPECT_NE(spec.mesh_crc32, 0u);
    EXPECT_TRUE(spec.model_path.empty());

    // 2. A session from the saved model, recorded and saved again.
    DemoOptions second = small_demo(dir, "second");
    second.workpiece = first.save;
    second.record = (dir / "second.trdx").string();
    second.save = (dir / "second.tdx").string();
    run_demo(second);
    const compute::TdxModel again = compute::load_tdx(second.save, std::size_t{1} << 30);
    const SessionSpec spec2 = spec_from_json(again.settings_json, second.save);
    EXPECT_EQ(spec2.model_path, fs::absolute(first.save).lexically_normal().string());
    EXPECT_EQ(spec2.model_bytes, fs::file_size(first.save));
    EXPECT_EQ(spec2.resolution, 32);
    EXPECT_TRUE(spec2.mesh_path.empty());
    EXPECT_EQ(again.to_world, saved.to_world);
    EXPECT_EQ(again.model.lattice.cells, saved.model.lattice.cells);
    EXPECT_LE(compute::dexel_volume_m3(again.model), compute::dexel_volume_m3(saved.model));  // carved further

    // 3. Its replay rebuilds the workpiece from the same model: the same mesh byte for byte.
    EXPECT_EQ(replay_error(second.record, dir / "replay"), "");
    EXPECT_EQ(test::bytes_of(dir / "replay" / "sculpted.ply"), test::bytes_of(dir / "second" / "sculpted.ply"));

    // 4. A model file that changed since the recording is refused.
    fs::copy_file(second.save, first.save, fs::copy_options::overwrite_existing);
    const std::string msg = replay_error(second.record, dir / "replay2");
    EXPECT_NE(msg.find("the workpiece model " + spec2.model_path + " changed since the recording"), std::string::npos)
        << msg;
}

TEST(ModelSessions, OutputsAndSourcesAreCheckedBeforeTheSession) {
    const fs::path dir = test::temp_dir("model_sessions_bad");
    DemoOptions d = small_demo(dir, "bad");
    d.save = "/dev/full/x.tdx";
    try {
        run_demo(d);
        ADD_FAILURE() << "an impossible --save was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("--save /dev/full/x.tdx: ", 0), 0u) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / "bad" / "report.json"));  // refused before the session ran
    d = small_demo(dir, "bad2");
    std::ofstream(dir / "junk.tdx") << "not a model";
    d.workpiece = (dir / "junk.tdx").string();
    try {
        run_demo(d);
        ADD_FAILURE() << "a junk model was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("junk.tdx: not a tridex model file"), std::string::npos) << e.what();
    }
}

TEST(ModelSessions, SceneWorkpieceModelIsResolvedAndExclusive) {
    const fs::path dir = test::temp_dir("model_scene");
    std::ofstream(dir / "m.tdx") << "x";  // the scene only names it; the session would load it
    std::ofstream(dir / "scene.json") << R"({ "workpiece": { "model": "m.tdx" } })";
    const RunScene scene = load_run_scene((dir / "scene.json").string());
    EXPECT_EQ(scene.spec.model_path, fs::absolute(dir / "m.tdx").lexically_normal().string());
    std::ofstream(dir / "both.json") << R"({ "workpiece": { "model": "m.tdx", "mesh": "bunny.off" } })";
    try {
        load_run_scene((dir / "both.json").string());
        ADD_FAILURE() << "model and mesh together were accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("field 'workpiece.mesh': not with workpiece.model"), std::string::npos)
            << e.what();
    }
    std::ofstream(dir / "missing.json") << R"({ "workpiece": { "model": "nope.tdx" } })";
    EXPECT_THROW(load_run_scene((dir / "missing.json").string()), Error);
}

// `run --workpiece FILE.tdx` starts from a saved model as `demo --workpiece` does, whatever the scene's workpiece.
TEST(ModelSessions, RunWorkpieceOptionStartsFromTheSavedModel) {
    const fs::path dir = test::temp_dir("model_run_option");
    std::ofstream(dir / "m.tdx") << "x";  // resolving only names it; the session would load it
    RunOptions o;
    o.display = "offscreen";
    o.out = (dir / "out").string();
    o.workpiece = (dir / "m.tdx").string();
    const RunSetup s = resolve_run(o);
    EXPECT_EQ(s.scene.spec.model_path, fs::absolute(dir / "m.tdx").lexically_normal().string());
    EXPECT_TRUE(s.scene.spec.mesh_path.empty());
    o.workpiece = (dir / "nope.tdx").string();
    try {
        (void)resolve_run(o);
        ADD_FAILURE() << "a missing --workpiece was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--workpiece: no such file"), std::string::npos) << e.what();
    }
    o.workpiece = (dir / "m.tdx").string();
    o.save = (dir / "m.tdx").string();
    EXPECT_THROW((void)resolve_run(o), Error) << "--save over the model the session starts from";
}

}  // namespace
}  // namespace tridex::app
