// app/commands/study/study_run.cpp - the study protocol for one participant: scripted through the haptic loop, or live
// as a sequence of `tridex run` sessions, one per phase.
#include "app/commands/study/study_run.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/support/json_file.hpp"
#include "app/support/output_dir.hpp"
#include "app/session/run/run_session.hpp"
#include "app/scene/study_recording.hpp"
#include "app/scene/study_objects.hpp"
#include "app/commands/study/study_sim.hpp"
#include "app/scene/trial_table.hpp"
#include "core/crc32.hpp"
#include "core/error.hpp"

namespace tridex::app::study {

namespace fs = std::filesystem;

namespace {

std::uint32_t participant_seed(const std::string& participant, std::uint32_t seed) {
    const std::uint32_t s = seed != 0 ? seed : crc32_ieee(participant.data(), participant.size());
    return s != 0 ? s : 1;
}

nlohmann::json look_json(const ObjectLook& l) {
    return {{"visible", l.visible}, {"felt", l.felt}, {"colour_on_contact", l.colour_on_contact}};
}

nlohmann::json model_json(const StudyModel& m) {
    return {{"tube", look_json(m.tube)}, {"funnels", look_json(m.funnels)}, {"caps", look_json(m.caps)}};
}

// One phase of the protocol.
struct Phase {
    std::string name;      // introduction, presentation, test_look, training, test
    std::string model;     // the study model shown
    double duration_s;     // timed phases: their time; test trials: the timeout
    int trial = 0;         // test trials: 1..n
    std::string line;      // what the overlay says
};

std::vector<Phase> protocol_phases(const ProtocolTimings& p, const std::string& group) {
    const std::string training = group + "_training";
    std::vector<Phase> v = {
        {"introduction", training, p.introduction_s, 0, "Introduction: hold the wand and get to know the device"},
        {"presentation", training, p.presentation_s, 0, "Presentation: this is the training model"},
        {"test_look", "test", p.test_look_s, 0, "Look at the test model: touch the start cap, go through to the end cap"},
        {"training", training, p.training_s, 0, "Training: guide the wand through the tube, again and again"},
    };
    for (int t = 1; t <= p.test_trials; ++t)
        v.push_back({"test", "test", p.trial_timeout_s, t,
                     "Test trial " + std::to_string(t) + ": touch the start cap, then go through to the end cap"});
    return v;
}

std::string hex_id(std::uint32_t id) {
    char s[16];
    std::snprintf(s, sizeof s, "%08x", id);
    return s;
}

// A phase as a live `tridex run` session: its scene file, run, and the recording of a test trial.
nlohmann::json run_live_phase(const StudyRunOptions& o, const StudyScene& scene, const Phase& ph, const fs::path& dir,
                              std::uint32_t seed) {
    const std::string stem = ph.trial > 0 ? "test_" + std::to_string(ph.trial) : ph.name;
    const fs::path phases = dir / "phases";
    fs::create_directories(phases);
    const std::string device = !o.device.empty() ? o.device : o.display == "offscreen" ? "simulated" : "spacemouse";
    // The scene's seed is 1..2^31-1: the participant's seed folded into that range.
    nlohmann::json sc = {
        {"study", {{"scene", scene.path}, {"model", ph.model}, {"seed", seed % 2147483647u + 1u}, {"trial", std::max(ph.trial, 1)},
                   {"end_at_end_cap", ph.trial > 0}, {"phase_line", ph.line}}},
        // The Falcon's own workspace; every device's gain fits the tube into its workspace, forces divided by it
        // (the scaling technique), so the walls feel as stiff on a small device as on the wand.
        {"device", {{"driver", device}, {"profile", device.rfind("falcon", 0) == 0 ? "falcon" : "wand"}}},
        {"workspace", {{"mode", "scaling"}, {"scale", "fit"}}},
        {"display", {{"preset", "desktop"}, {"stereo", "mono"}, {"resolution", {800, 450}},
                     {"screen", {{"lower_left", {-0.4, -0.225, 0.0}}, {"lower_right", {0.4, -0.225, 0.0}},
                                 {"upper_left", {-0.4, 0.225, 0.0}}}}}},
        {"head", {{"provider", "fixed"}, {"position_m", {0.0, 0.2, 1.0}}}}};
    if (ph.trial > 0) {
        sc["study"]["participant"] = o.participant;
        sc["study"]["group"] = o.group;
    }
    const fs::path scene_file = phases / (stem + ".json");
    write_json_file(scene_file.string(), sc);
    RunOptions ro;
    ro.scene = scene_file.string();
    ro.display = o.display;
    ro.display_config = o.display_config;
    ro.out = (phases / stem).string();
    ro.seconds = ph.duration_s;
    ro.no_journal = true;
    ro.validate = o.validate;
    ro.checkpoint_s = 0.0;
    const std::string file = "trial_" + std::to_string(ph.trial) + ".trdx";
    if (ph.trial > 0) ro.record = (dir / file).string();
    const RunResult r = [&] {
        try {
            return run_stereo_session(ro);
        } catch (const Error& e) {
            throw Error("study run: phase " + stem + ": " + e.what());
        }
    }();
    nlohmann::json j = {{"phase", ph.name}, {"model", ph.model}, {"duration_s", r.session_s}, {"scene", scene_file.string()},
                        {"ended", r.notes.empty() ? "" : r.notes.front()}, {"study", r.study}};
    if (ph.trial > 0) {
        j["trial"] = ph.trial;
        j["recording"] = file;
        j["reached_end_cap"] = r.study.value("trial_done", false);
    } else {
        j["timed_s"] = ph.duration_s;
    }
    return j;
}

}  // namespace

devices::Recording simulated_test_trial(const StudyScene& scene, const std::string& participant,
                                        const std::string& group, int trial, std::uint32_t seed) {
    SimulatedPass pass = simulate_pass(scene, "test", participant_seed(participant, seed), trial);
    const StudyTag tag{participant, group, trial, "test", scene.tube.name, tube_id(scene.tube)};
    pass.recording.header.notes = tag_notes(pass.recording.header.notes, tag);
    return std::move(pass.recording);
}

void run_study_protocol(const StudyRunOptions& o) {
    if (!valid_participant_id(o.participant))
        throw Error("--participant '" + o.participant + "': an ID of 1..64 letters, digits, '_' or '-' (no names)");
    const auto& groups = study_groups();
    if (std::find(groups.begin(), groups.end(), o.group) == groups.end())
        throw Error("--group '" + o.group + "': use haptic or visual");
    if (o.display != "window" && o.display != "fullscreen" && o.display != "offscreen")
        throw Error("--display '" + o.display + "': use window, fullscreen or offscreen");
    if (o.simulated && !o.device.empty()) throw Error("--device: --simulated plays the scripted participant; drop one");
    const StudyScene scene = read_study_scene(o.scene.empty() ? default_study_scene_path() : o.scene);
    const fs::path dir = fs::path(o.out) / o.participant;
    std::error_code ec;
    if (fs::exists(dir, ec))
        throw Error("--out " + dir.string() + ": this participant's folder exists already; a participant runs once");
    prepare_output_dir(dir.string(), "--out");

    const std::uint32_t seed = participant_seed(o.participant, o.seed);
    const ProtocolTimings& p = scene.protocol;
    nlohmann::json phases = nlohmann::json::array();
    nlohmann::json trials = nlohmann::json::array();
    for (const Phase& ph : protocol_phases(p, o.group)) {
        const StudyModel& look = study_model(scene, ph.model, "phase " + ph.name);
        nlohmann::json j;
        if (!o.simulated) {
            std::printf("%s (%s): %s\n", o.participant.c_str(), o.group.c_str(), ph.line.c_str());
            std::fflush(stdout);
            j = run_live_phase(o, scene, ph, dir, seed);
        } else if (ph.trial > 0) {
            const devices::Recording rec = simulated_test_trial(scene, o.participant, o.group, ph.trial, o.seed);
            devices::write_recording((dir / ("trial_" + std::to_string(ph.trial) + ".trdx")).string(), rec);
            const double duration = rec.ticks.back().t_s - rec.ticks.front().t_s;
            j = {{"phase", "test"}, {"model", "test"}, {"trial", ph.trial}, {"duration_s", duration},
                 {"recording", "trial_" + std::to_string(ph.trial) + ".trdx"}};
        } else if (ph.name == "training") {
            // The scripted participant does not learn: one pass through the group's training model in the loop.
            const SimulatedPass pass = simulate_pass(scene, ph.model, seed, 0);
            j = {{"phase", ph.name}, {"model", ph.model}, {"duration_s", p.training_s},
                 {"simulated_pass", {{"duration_s", pass.duration_s}, {"ticks", pass.ticks},
                                     {"contact_ticks", pass.contact_ticks}, {"tube_touch_ticks", pass.tube_touch_ticks},
                                     {"max_force_n", pass.max_force_n}}}};
        } else {
            j = {{"phase", ph.name}, {"model", ph.model}, {"duration_s", ph.duration_s}};
        }
        j["look"] = model_json(look);
        if (ph.trial > 0) {
            trials.push_back(j["recording"]);
            std::printf("%s (%s) test trial %d: %s, %.1f s\n", o.participant.c_str(), o.group.c_str(), ph.trial,
                        (dir / j["recording"].get<std::string>()).string().c_str(), j["duration_s"].get<double>());
        }
        phases.push_back(j);
    }
    write_json_file((dir / "protocol.json").string(),
                    {{"participant", o.participant}, {"group", o.group}, {"simulated", o.simulated},
                     {"display", o.simulated ? "none" : o.display}, {"scene", scene.path}, {"tube", scene.tube.name},
                     {"tube_id", hex_id(tube_id(scene.tube))}, {"phases", phases}, {"recordings", trials}});
}

}  // namespace tridex::app::study
