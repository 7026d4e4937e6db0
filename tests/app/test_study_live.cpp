// The study scenes in live sessions, through the executable as a user runs them: `tridex run` of the bundled
// model scenes offscreen (the tube drawn and coloured by contact, the felt walls invisible), and the live protocol
// `tridex study run` offscreen with the scripted participant on the simulated device: the phases in order, each
// test trial gated by the end cap, recordings only of the test trials, which `study analyze` reads.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "../test_paths.hpp"
#include "renderer/image/image.hpp"
#include "test_files.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using test::read_json;
using test::run_tridex;

// The bundled assets (read when a test runs, from ctest's environment).
fs::path assets() { return TRIDEX_ASSETS_DIR; }

// Pixels of the image whose colour is clearly red / clearly green (the contact colours over the dark background).
int count_pixels(const renderer::Image& im, bool red) {
    int n = 0;
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const std::uint8_t* p = &im.rgba[4 * (static_cast<std::size_t>(y) * im.width + x)];
            const int r = p[0], g = p[1], b = p[2];
            n += red ? (r > 120 && r > 2 * g && r > 2 * b) : (g > 90 && g > r + 40 && g > b + 40);
        }
    return n;
}

TEST(StudyLive, ModelScenesShowTheTubeAndItsContactColour) {
    const fs::path dir = fs::temp_directory_path() / "tridex_study_live_scenes";
    fs::remove_all(dir);
    // Visual training, stopped half way through (the scripted wand wanders into the wall on the way).
    const auto v = run_tridex("run " + (assets() / "study_visual_training.json").string() +
                                  " --display offscreen --validate --out " + (dir / "visual").string(),
                              dir / "visual_run");
    ASSERT_EQ(v.exit_code, 0) << v.err;
    const auto rv = read_json(dir / "visual" / "report.json");
    EXPECT_EQ(rv["validation_messages"], 0);
    EXPECT_EQ(rv["study"]["model"], "visual_training");
    EXPECT_GT(rv["study"]["frames_touching"]["tube"].get<int>(), 0);
    EXPECT_TRUE(rv["study"]["trial_done"].get<bool>());  // the scripted hand went from cap to cap
    EXPECT_EQ(rv["haptics"]["contact_ticks"], 0);         // the visual tube has no force
    const renderer::Image left = renderer::read_png((dir / "visual" / "left.png").string());
    EXPECT_GT(count_pixels(left, false), 500);  // the green tube (not touched at the end cap)
    // Haptic training: the walls are felt (contact ticks) but the tube is not drawn.
    const auto h = run_tridex("run " + (assets() / "study_haptic_training.json").string() +
                                  " --display offscreen --validate --out " + (dir / "haptic").string(),
                              dir / "haptic_run");
    ASSERT_EQ(h.exit_code, 0) << h.err;
    const auto rh = read_json(dir / "haptic" / "report.json");
    EXPECT_EQ(rh["validation_messages"], 0);
    EXPECT_GT(rh["haptics"]["contact_ticks"].get<int>(), 0);
    EXPECT_GT(rh["study"]["frames_touching"]["tube"].get<int>(), 0);
    EXPECT_LE(rh["haptics"]["max_force_n"].get<double>(), 10.0);
    // The end cap is red in both final frames (both wand points on it); the visual tube green, the haptic one absent.
    const renderer::Image hl = renderer::read_png((dir / "haptic" / "left.png").string());
    EXPECT_GT(count_pixels(hl, true), 50);
    EXPECT_GT(count_pixels(left, true), 50);
    EXPECT_LT(count_pixels(hl, false), count_pixels(left, false));
    // A scene that sets both a study and a workpiece is refused with one line naming the field.
    std::ofstream(dir / "bad.json") << R"({"study": {"scene": ")" << (assets() / "study_tube_scene.json").string()
                                    << R"("}, "workpiece": {"resolution": 64}})";
    const auto b = run_tridex("run " + (dir / "bad.json").string() + " --display offscreen --frames 1 --out " +
                                  (dir / "bad").string(),
                              dir / "bad_run");
    EXPECT_EQ(b.exit_code, 2);
    EXPECT_NE(b.err.find("field 'workpiece'"), std::string::npos) << b.err;
}

// The study on a small device: the emulated Falcon (its own 80 mm workspace) with a fitted device -> world gain
// reaches the whole tube, feels its walls with forces divided by the gain, and a replay of the recording rebuilds
// the felt walls from the study scene and feels the same contacts.
TEST(StudyLive, TheFalconReachesTheTubeThroughAFittedGainAndAReplayFeelsTheSameWalls) {
    const fs::path dir = fs::temp_directory_path() / ("tridex_study_falcon_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    nlohmann::json sc = read_json(assets() / "study_haptic_training.json");
    sc["study"]["scene"] = (assets() / "study_tube_scene.json").string();
    sc["device"] = {{"driver", "falcon-emulator"}, {"profile", "falcon"}};
    sc["workspace"] = {{"mode", "scaling"}, {"scale", "fit"}};
    std::ofstream(dir / "falcon.json") << sc.dump();
    const auto r = run_tridex("run " + (dir / "falcon.json").string() + " --display offscreen --out " +
                                  (dir / "out").string() + " --record " + (dir / "trial.trdx").string(),
                              dir / "run");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto rep = read_json(dir / "out" / "report.json");
    const double gain = rep["settings"]["workspace_scale"].get<double>();
    EXPECT_GT(gain, 4.0);  // a tube of about 0.45 m in a workspace of 80 mm
    EXPECT_TRUE(rep["study"]["trial_done"].get<bool>());
    EXPECT_GT(rep["haptics"]["contact_ticks"].get<int>(), 0);
    for (int a = 0; a < 3; ++a) EXPECT_LT(rep["haptics"]["device_extent_m"][a].get<double>(), 0.08) << a;
    EXPECT_GT(rep["haptics"]["tool_world_extent_m"][0].get<double>(), 0.3);
    // The replay rebuilds the walls from the recorded study scene and model.
    const auto p = run_tridex("replay " + (dir / "trial.trdx").string() + " --out " + (dir / "replay").string(),
                              dir / "replay_run");
    ASSERT_EQ(p.exit_code, 0) << p.err;
    const auto rp = read_json(dir / "replay" / "report.json");
    EXPECT_EQ(rp["haptics"]["contact_ticks"], rep["haptics"]["contact_ticks"]);
    EXPECT_EQ(rp["haptics"]["max_force_n"], rep["haptics"]["max_force_n"]);
    // Without the fitted gain the scripted participant cannot reach the tube, and the message says what helps.
    sc["workspace"] = {{"mode", "scaling"}, {"scale", 1.0}};
    std::ofstream(dir / "unfit.json") << sc.dump();
    const auto u = run_tridex("run " + (dir / "unfit.json").string() + " --display offscreen --out " +
                                  (dir / "unfit").string(),
                              dir / "unfit_run");
    EXPECT_EQ(u.exit_code, 2);
    EXPECT_NE(u.err.find("\"scale\": \"fit\""), std::string::npos) << u.err;
    fs::remove_all(dir);
}

TEST(StudyLive, ProtocolPhasesInOrderWithTestTrialsGatedByTheEndCap) {
    const fs::path dir = fs::temp_directory_path() / "tridex_study_live_protocol";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // The bundled tube with a short protocol.
    std::ifstream in(assets() / "study_tube_scene.json");
    nlohmann::json scene = nlohmann::json::parse(in);
    scene["protocol"] = {{"introduction_s", 0.5}, {"presentation_s", 0.5}, {"test_look_s", 0.5}, {"training_s", 1.0},
                         {"test_trials", 2}, {"trial_timeout_s", 120}};
    std::ofstream(dir / "short.json") << scene.dump();
    const std::string study = (dir / "study").string();
    // W1: an ID whose derived seed is above 2^31 (the phase scenes must still take it).
    const auto r = run_tridex("study run --participant W1 --group visual --display offscreen --validate --scene " +
                                  (dir / "short.json").string() + " --out " + study,
                              dir / "run");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto p = read_json(dir / "study" / "W1" / "protocol.json");
    ASSERT_EQ(p["phases"].size(), 6u);
    const char* names[] = {"introduction", "presentation", "test_look", "training", "test", "test"};
    const char* models[] = {"visual_training", "visual_training", "test", "visual_training", "test", "test"};
    for (int i = 0; i < 6; ++i) {
        EXPECT_EQ(p["phases"][i]["phase"], names[i]) << i;
        EXPECT_EQ(p["phases"][i]["model"], models[i]) << i;
        EXPECT_EQ(p["phases"][i]["study"]["model"], models[i]) << i;
    }
    for (int i = 4; i < 6; ++i) {
        EXPECT_TRUE(p["phases"][i]["reached_end_cap"].get<bool>()) << i;
        EXPECT_EQ(p["phases"][i]["ended"], "ended: the wand reached the end cap") << i;
    }
    EXPECT_EQ(p["phases"][3]["ended"], "ended: --seconds 1 passed");
    // Recordings: the test trials only.
    std::vector<std::string> recordings;
    for (const auto& e : fs::recursive_directory_iterator(dir / "study"))
        if (e.path().extension() == ".trdx") recordings.push_back(e.path().filename().string());
    std::sort(recordings.begin(), recordings.end());
    EXPECT_EQ(recordings, (std::vector<std::string>{"trial_1.trdx", "trial_2.trdx"}));
    for (const char* ph : {"introduction", "training", "test_1"})
        EXPECT_EQ(read_json(dir / "study" / "W1" / "phases" / ph / "report.json")["validation_messages"], 0);
    // `study analyze` reads them as the participant's trials against the same tube.
    const auto a = run_tridex("study analyze " + study + " --scene " + (dir / "short.json").string() + " --out " +
                                  (dir / "analysis").string(),
                              dir / "analyze");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    std::ifstream csv(dir / "analysis" / "study_trials.csv");
    std::string header, row1, row2;
    std::getline(csv, header);
    std::getline(csv, row1);
    std::getline(csv, row2);
    EXPECT_EQ(row1.rfind("W1,visual,1,", 0), 0u) << row1;
    EXPECT_EQ(row2.rfind("W1,visual,2,", 0), 0u) << row2;
}

}  // namespace
}  // namespace tridex::app
