// app/scene/study_participant.hpp - the scripted participant of the study: where its hand takes the wand
// through the tube, as timed waypoints for the simulated device's virtual hand.
#pragma once

#include <cstdint>
#include <vector>

#include "app/scene/study_scene.hpp"
#include "core/math.hpp"

namespace tridex::app::study {

/// The hand's path of one pass from the start cap to the end cap, world m.
struct ParticipantPath {
    std::vector<double> t_s;     ///< waypoint times, s, strictly increasing from 0
    std::vector<Vec3> centre_m;  ///< the wand centre's target (midway between its two points), world m
    double speed_m_s = 0.0;      ///< the steady speed along the spine, m/s
    double wander_m = 0.0;       ///< amplitude of the lateral wander, m
};

/// The scripted participant: the wand held upright, its centre dwelling `dwell_s` (s) on the start cap, then
/// following the spine from the start cap to the end cap at a steady speed with a smooth lateral wander (two
/// sinusoids per axis across the spine, fading to zero at the caps), then dwelling `dwell_s` on the end cap;
/// a waypoint every 10 ms. `seed` picks the speed (0.05..0.09 m/s), the wander's amplitude (8..20 mm) and its
/// phases; the same seed and trial give the same path.
ParticipantPath scripted_participant_path(const StudyScene& scene, std::uint32_t seed, int trial, double dwell_s = 0.3);

}  // namespace tridex::app::study
