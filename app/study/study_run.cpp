// app/study/study_run.cpp - the study protocol for one participant, with a scripted participant for tests.
#include "app/study/study_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>

#include "app/json_file.hpp"
#include "app/output_dir.hpp"
#include "app/study/study_recording.hpp"
#include "app/study/trial_table.hpp"
#include "core/crc32.hpp"
#include "core/error.hpp"

namespace tridex::app::study {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::uint32_t participant_seed(const std::string& participant, std::uint32_t seed) {
    return seed != 0 ? seed : crc32_ieee(participant.data(), participant.size());
}

nlohmann::json look_json(const ObjectLook& l) {
    return {{"visible", l.visible}, {"felt", l.felt}, {"colour_on_contact", l.colour_on_contact}};
}

nlohmann::json model_json(const StudyModel& m) {
    return {{"tube", look_json(m.tube)}, {"funnels", look_json(m.funnels)}, {"caps", look_json(m.caps)}};
}

}  // namespace

devices::Recording simulated_test_trial(const StudyScene& scene, const std::string& participant,
                                        const std::string& group, int trial, std::uint32_t seed) {
    const Tube tube(scene.tube);
    std::mt19937 rng(participant_seed(participant, seed) * 2654435761u + static_cast<std::uint32_t>(trial));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double speed = 0.05 + 0.04 * unit(rng);
    const double amp = 0.008 + 0.012 * unit(rng);
    double phase[4], cycles[4];
    for (int k = 0; k < 4; ++k) phase[k] = 2.0 * kPi * unit(rng), cycles[k] = 1.0 + 3.0 * unit(rng);

    devices::Recording rec;
    rec.header.device_name = "wand";
    rec.header.period_s = 1e-3;
    rec.header.workspace_mode = "peng_moving";
    const StudyTag tag{participant, group, trial, "test", scene.tube.name, tube_id(scene.tube)};
    rec.header.notes = tag_notes(R"({"simulated_participant": true})", tag);

    const double s0 = tube.start_cap_s_m(), s1 = tube.end_cap_s_m();
    const double travel_s = (s1 - s0) / speed, dwell_s = 0.3;
    const int ticks = static_cast<int>(std::ceil((travel_s + 2.0 * dwell_s) / 1e-3)) + 1;
    const Vec3 half_wand(0.0, 0.5 * scene.wand_length_m, 0.0);
    for (int i = 0; i < ticks; ++i) {
        const double t = 1e-3 * i;
        const double u = std::clamp((t - dwell_s) / travel_s, 0.0, 1.0);  // progress from cap to cap
        const double s = s0 + u * (s1 - s0);
        const Vec3 tangent = tube.tangent_at(s);
        const Vec3 up = std::fabs(tangent.y) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
        const Vec3 a = glm::normalize(glm::cross(tangent, up)), b = glm::cross(a, tangent);
        const double fade = std::sin(kPi * u);
        const double wa = amp * fade * 0.5 * (std::sin(2 * kPi * cycles[0] * u + phase[0]) + std::sin(2 * kPi * cycles[1] * u + phase[1]));
        const double wb = amp * fade * 0.5 * (std::sin(2 * kPi * cycles[2] * u + phase[2]) + std::sin(2 * kPi * cycles[3] * u + phase[3]));
        const Vec3 centre = tube.point_at(s) + wa * a + wb * b;
        devices::RecordedTick k;
        k.t_s = t;
        k.device.t_s = t;
        k.device.pose.position = centre;
        k.device.velocity_m_s = speed * tangent * (u > 0.0 && u < 1.0 ? 1.0 : 0.0);
        k.wand_centre_m = centre;
        k.top_m = centre + half_wand;
        k.bottom_m = centre - half_wand;
        k.top_contact_m = k.top_m;  // the test model has no tube: nothing is touched on the way
        k.bottom_contact_m = k.bottom_m;
        rec.ticks.push_back(k);
    }
    return rec;
}

void run_study_protocol(const StudyRunOptions& o) {
    if (!valid_participant_id(o.participant))
        throw Error("--participant '" + o.participant + "': an ID of 1..64 letters, digits, '_' or '-' (no names)");
    const auto& groups = study_groups();
    if (std::find(groups.begin(), groups.end(), o.group) == groups.end())
        throw Error("--group '" + o.group + "': use haptic or visual");
    if (!o.simulated)
        throw Error("study run: live sessions with a person at the wand are not wired yet; use --simulated");
    const StudyScene scene = read_study_scene(o.scene.empty() ? default_study_scene_path() : o.scene);
    const std::filesystem::path dir = std::filesystem::path(o.out) / o.participant;
    std::error_code ec;
    if (std::filesystem::exists(dir, ec))
        throw Error("--out " + dir.string() + ": this participant's folder exists already; a participant runs once");
    prepare_output_dir(dir.string(), "--out");

    const ProtocolTimings& p = scene.protocol;
    const StudyModel& training = o.group == "haptic" ? scene.haptic_training : scene.visual_training;
    nlohmann::json phases = nlohmann::json::array();
    phases.push_back({{"phase", "introduction"}, {"duration_s", p.introduction_s}});
    phases.push_back({{"phase", "presentation"}, {"model", o.group + "_training"}, {"duration_s", p.presentation_s}});
    phases.push_back({{"phase", "test_look"}, {"model", "test"}, {"duration_s", p.test_look_s}});
    phases.push_back({{"phase", "training"}, {"model", o.group + "_training"}, {"duration_s", p.training_s},
                      {"look", model_json(training)}});
    nlohmann::json trials = nlohmann::json::array();
    for (int trial = 1; trial <= p.test_trials; ++trial) {
        const devices::Recording rec = simulated_test_trial(scene, o.participant, o.group, trial, o.seed);
        const std::string file = "trial_" + std::to_string(trial) + ".trdx";
        devices::write_recording((dir / file).string(), rec);
        const double duration = rec.ticks.back().t_s - rec.ticks.front().t_s;
        phases.push_back({{"phase", "test"}, {"model", "test"}, {"trial", trial}, {"duration_s", duration},
                          {"recording", file}, {"look", model_json(scene.test)}});
        trials.push_back(file);
        std::printf("%s (%s) test trial %d: %s, %.1f s\n", o.participant.c_str(), o.group.c_str(), trial,
                    (dir / file).string().c_str(), duration);
    }
    char id[16];
    std::snprintf(id, sizeof id, "%08x", tube_id(scene.tube));
    write_json_file((dir / "protocol.json").string(),
                    {{"participant", o.participant}, {"group", o.group}, {"simulated", o.simulated},
                     {"scene", scene.path}, {"tube", scene.tube.name}, {"tube_id", id}, {"phases", phases},
                     {"recordings", trials}});
}

}  // namespace tridex::app::study
