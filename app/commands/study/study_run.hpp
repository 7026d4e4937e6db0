// app/commands/study/study_run.hpp - `tridex study run`: one participant through the protocol of the thesis
// (Singapogu 2007, 4.2.2, Fig. 32, Appendix C), recording only the test trials.
#pragma once

#include <cstdint>
#include <string>

#include "app/scene/study_scene.hpp"
#include "devices/recording.hpp"

namespace tridex::app::study {

/// Options of `tridex study run --participant ID --group haptic|visual [--simulated] [--scene FILE] --out DIR`.
struct StudyRunOptions {
    std::string participant;       ///< participant ID only (valid_participant_id), never a name
    std::string group;             ///< "haptic" or "visual": the training model the participant gets
    bool simulated = false;        ///< play a scripted participant through the haptic loop, no window, no GPU
    std::string scene;             ///< study scene ("" = the bundled assets/study_tube_scene.json)
    std::string out = "out/study"; ///< the participant's files go to OUT/<participant>/
    std::uint32_t seed = 0;        ///< scripted participant: 0 = derived from the participant ID
    /// Live protocol (without --simulated): where each phase is shown (window | fullscreen | offscreen; offscreen
    /// plays the scripted participant on the simulated device, for tests) and the device driver of the phases'
    /// scenes (simulated, mouse, spacemouse, falcon, ...: a scene's device.driver, with the wand profile where the
    /// driver has no profile of its own; "" = simulated offscreen, spacemouse in a window).
    std::string display = "window";
    std::string device;
    std::string display_config;    ///< a display config file for the phases (`run --display-config`); "" = desktop
    bool validate = false;         ///< Vulkan validation in the live phases
};

/// The scripted participant's test trial `trial` through the real haptic loop (simulate_pass with the test model
/// and the seed of `participant` and `seed`), tagged as a study recording (participant, group, trial, the tube).
devices::Recording simulated_test_trial(const StudyScene& scene, const std::string& participant,
                                        const std::string& group, int trial, std::uint32_t seed);

/// Runs the protocol: introduction, presentation of the training model, a look at the test model, timed training
/// (the group's model), then protocol.test_trials untimed test trials each ended by the end cap (or the trial
/// timeout); writes OUT/<participant>/trial_<n>.trdx per test trial (nothing else is recorded) and
/// OUT/<participant>/protocol.json (participant, group, scene, tube id, the phases with their durations, the trial
/// files). With `simulated` the phases take no wall time: training is one scripted pass through the group's model
/// in the haptic loop (its contact counts go into protocol.json), the trials are simulated_test_trial's.
/// Without it each phase is a `tridex run` session of the phase's model (its scene file written to
/// OUT/<participant>/phases/, its outputs beside it) with an overlay line saying the phase and what to do;
/// timed phases end after their time, test trials when both wand points touched the end cap after the start cap.
/// Throws tridex::Error (one line) for a bad ID or group, a bad scene, an unwritable --out, an existing
/// participant folder, or a phase that fails.
void run_study_protocol(const StudyRunOptions& options);

}  // namespace tridex::app::study
