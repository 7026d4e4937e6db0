// `tridex study` end to end through the executable: scripted participants run the protocol, their test recordings
// are analysed against the reference tube, the statistics computed; bad input exits 2 with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "app/commands/study/study_run.hpp"
#include "app/scene/study_scene.hpp"
#include "app/scene/tube.hpp"
#include "test_files.hpp"

namespace tridex::app::study {
namespace {

using test::read_json;
using test::run_tridex;

TEST(StudyRun, ScriptedParticipantStaysNearTheSpineAndTouchesBothCaps) {
    const StudyScene scene = read_study_scene(default_study_scene_path());
    const Tube tube(scene.tube);
    const devices::Recording rec = simulated_test_trial(scene, "P01", "haptic", 1, 0);
    ASSERT_GT(rec.ticks.size(), 1000u);
    EXPECT_TRUE(tube.touches_start_cap(rec.ticks.front().top_m));
    EXPECT_TRUE(tube.touches_start_cap(rec.ticks.front().bottom_m));
    EXPECT_TRUE(tube.touches_end_cap(rec.ticks.back().bottom_m));
    // Driven through the haptic loop by the virtual hand (the test model feels only the funnels): the wand's
    // centre stays within the wander's largest amplitude of the spine.
    for (const auto& t : rec.ticks) ASSERT_LT(tube.project(0.5 * (t.top_m + t.bottom_m)).distance_m, 0.025);
    // The same ID and trial give the same participant; another seed another one.
    EXPECT_EQ(simulated_test_trial(scene, "P01", "haptic", 1, 0).ticks.size(), rec.ticks.size());
    EXPECT_NE(simulated_test_trial(scene, "P01", "haptic", 1, 77).ticks.size(), rec.ticks.size());
}

TEST(StudyRun, WholePipelineThroughTheExecutable) {
    const auto dir = std::filesystem::temp_directory_path() / "tridex_study_run_test";
    std::filesystem::remove_all(dir);
    const std::string study = (dir / "study").string();
    for (int i = 1; i <= 3; ++i)
        for (const char* g : {"haptic", "visual"}) {
            const std::string id = std::string(g == std::string("haptic") ? "H" : "V") + std::to_string(i);
            const auto r = run_tridex("study run --participant " + id + " --group " + g + " --simulated --out " + study,
                                      dir / ("run_" + id));
            ASSERT_EQ(r.exit_code, 0) << r.err;
            ASSERT_TRUE(std::filesystem::exists(dir / "study" / id / "trial_2.trdx"));
            const auto protocol = read_json(dir / "study" / id / "protocol.json");
            EXPECT_EQ(protocol["phases"].size(), 6u);  // introduction, presentation, test look, training, 2 trials
            EXPECT_EQ(protocol["phases"][3]["phase"], "training");
        }
    const auto a = run_tridex("study analyze " + study + " --out " + (dir / "out").string(), dir / "analyze");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / "deviation_haptic.png"));
    const auto s = run_tridex("study stats " + (dir / "out" / "study_trials.csv").string() + " --out " + (dir / "out").string(),
                              dir / "stats");
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const auto j = read_json(dir / "out" / "study_stats.json");
    EXPECT_EQ(j["groups"]["haptic"]["trials"], 6);
    EXPECT_TRUE(j["mann_whitney"]["time_s"]["p_exact"].is_number());
    EXPECT_EQ(j["per_participant"]["mann_whitney"]["time_s"]["n1"], 3);

    // Bad input: one line on stderr, exit 2.
    auto one_line_2 = [&](const std::string& args, const std::string& what) {
        const auto r = run_tridex(args, dir / "bad");
        EXPECT_EQ(r.exit_code, 2) << args;
        EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    };
    one_line_2("study run --participant 'Jane Doe' --group haptic --simulated --out " + study, "no names");
    one_line_2("study run --participant H1 --group haptic --simulated --out " + study, "exists already");
    one_line_2("study run --participant Z9 --group tactile --simulated --out " + study, "--group");
    std::ofstream(dir / "bad.csv") << "participant,group,trial,time_s,deviation_m\nP1,haptic,1,2,x\n";
    one_line_2("study stats " + (dir / "bad.csv").string(), "bad.csv:2: field 'deviation_m': not a number");
    std::ofstream(dir / "straight.json") << R"({"tube": {"spine_m": [[-0.18, 0, 0.3], [0.18, 0, 0.3]]}})";
    one_line_2("study analyze " + study + " --scene " + (dir / "straight.json").string(), "not the reference tube");
}

}  // namespace
}  // namespace tridex::app::study
