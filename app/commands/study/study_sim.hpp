// app/commands/study/study_sim.hpp - the scripted participant through the real haptic loop: the simulated device's
// virtual hand follows the participant's path, the 1 kHz HapticLoop (stepped in device time) feels the model's
// felt walls through the multi-point god-object, and its tick records become the trial's recording.
#pragma once

#include <cstdint>
#include <string>

#include "app/scene/study_participant.hpp"
#include "app/scene/study_scene.hpp"
#include "devices/recording.hpp"

namespace tridex::app::study {

/// One pass of the scripted participant through one model.
struct SimulatedPass {
    devices::Recording recording;  ///< every tick (the session recording format, settings in the notes)
    double duration_s = 0.0;       ///< device time of the pass, s
    std::size_t ticks = 0;         ///< haptic ticks
    std::size_t contact_ticks = 0; ///< ticks with a wand point's god-object on a felt wall
    std::size_t tube_touch_ticks = 0;  ///< ticks the tube would show its contact colour (study_contact: either point)
    double max_force_n = 0.0;      ///< largest force the loop sent to the device, N
};

/// Runs the scripted participant (scripted_participant_path with `seed`, `trial`) through `model` (a name of
/// study_model): the felt walls (felt_walls) as the haptic loop's active surface (extract_active_surface around
/// the tool every 5 ticks), a SimulatedDevice with the wand profile whose hand follows the path (device home on
/// the path's centre, scale 1), and a HapticLoop with loop_config of the wand's spec (flat end of the wand's
/// radius and length, two points, op none, no friction), stepped tick by tick in device time until the path's
/// end plus 0.2 s. The result is the same for the same inputs. Throws tridex::Error for a bad scene or model,
/// or when the path leaves the wand's workspace. `path`, when given, replaces the scripted participant's path
/// (the wand centre's target, world m; seed and trial are then unused).
SimulatedPass simulate_pass(const StudyScene& scene, const std::string& model, std::uint32_t seed, int trial,
                            const ParticipantPath* path = nullptr);

}  // namespace tridex::app::study
