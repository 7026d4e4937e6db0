// app/study/study_run.hpp - `tridex study run`: one participant through the protocol of the thesis
// (Singapogu 2007, 4.2.2, Fig. 32, Appendix C), recording only the test trials.
#pragma once

#include <cstdint>
#include <string>

#include "app/study/study_scene.hpp"
#include "devices/recording.hpp"

namespace tridex::app::study {

/// Options of `tridex study run --participant ID --group haptic|visual [--simulated] [--scene FILE] --out DIR`.
struct StudyRunOptions {
    std::string participant;       ///< participant ID only (valid_participant_id), never a name
    std::string group;             ///< "haptic" or "visual": the training model the participant gets
    bool simulated = false;        ///< play a scripted participant instead of a person at a device
    std::string scene;             ///< study scene ("" = the bundled assets/study_tube_scene.json)
    std::string out = "out/study"; ///< the participant's files go to OUT/<participant>/
    std::uint32_t seed = 0;        ///< scripted participant: 0 = derived from the participant ID
};

/// The scripted participant of one test trial: the wand held upright (its top and bottom points wand_length_m
/// apart along world +y) whose centre dwells 0.3 s at the start cap, follows the spine from the start cap to the
/// end cap at a steady speed with a smooth lateral wander (two sinusoids per axis across the spine, fading to
/// zero at the caps), and dwells 0.3 s at the end cap; one tick per millisecond. `seed` picks the speed
/// (0.05..0.09 m/s) and the wander's amplitude (8..20 mm) and phases. The recording carries the study tag; the
/// device sample is the wand centre in the world frame (the simulated device's frame is the world's here).
devices::Recording simulated_test_trial(const StudyScene& scene, const std::string& participant,
                                        const std::string& group, int trial, std::uint32_t seed);

/// Runs the protocol: introduction, presentation of the training model, a look at the test model, timed training
/// (the group's model), then protocol.test_trials untimed test trials each ended by the end cap; writes
/// OUT/<participant>/trial_<n>.trdx per test trial (nothing else is recorded) and OUT/<participant>/protocol.json
/// (participant, group, scene, tube id, the phases with their durations, the trial files). With `simulated` the
/// phases take no wall time and the trials are simulated_test_trial's. Without it, throws tridex::Error: live
/// runs need a session with a person at a device, which this build does not drive yet. Throws tridex::Error
/// (one line) for a bad ID or group, a bad scene, an unwritable --out, or an existing participant folder.
void run_study_protocol(const StudyRunOptions& options);

}  // namespace tridex::app::study
