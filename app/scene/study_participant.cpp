// app/scene/study_participant.cpp - the scripted participant's hand path through the tube.
#include "app/scene/study_participant.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "app/scene/tube.hpp"

namespace tridex::app::study {

ParticipantPath scripted_participant_path(const StudyScene& scene, std::uint32_t seed, int trial, double dwell_s) {
    constexpr double kPi = std::numbers::pi, kStep = 0.01;
    const Tube tube(scene.tube);
    std::mt19937 rng(seed * 2654435761u + static_cast<std::uint32_t>(trial));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    ParticipantPath p;
    p.speed_m_s = 0.05 + 0.04 * unit(rng);
    p.wander_m = 0.008 + 0.012 * unit(rng);
    double phase[4], cycles[4];
    for (int k = 0; k < 4; ++k) phase[k] = 2.0 * kPi * unit(rng), cycles[k] = 1.0 + 3.0 * unit(rng);
    const double s0 = tube.start_cap_s_m(), s1 = tube.end_cap_s_m();
    const double travel_s = (s1 - s0) / p.speed_m_s, total_s = travel_s + 2.0 * dwell_s;
    const int n = static_cast<int>(std::ceil(total_s / kStep));
    for (int i = 0; i <= n; ++i) {
        const double t = total_s * i / n;
        const double u = std::clamp((t - dwell_s) / travel_s, 0.0, 1.0);  // progress from cap to cap
        const double s = s0 + u * (s1 - s0);
        Vec3 a, b;
        plane_axes(tube.tangent_at(s), a, b);
        const double fade = std::sin(kPi * u);
        const double wa = p.wander_m * fade * 0.5 *
                          (std::sin(2 * kPi * cycles[0] * u + phase[0]) + std::sin(2 * kPi * cycles[1] * u + phase[1]));
        const double wb = p.wander_m * fade * 0.5 *
                          (std::sin(2 * kPi * cycles[2] * u + phase[2]) + std::sin(2 * kPi * cycles[3] * u + phase[3]));
        p.t_s.push_back(t);
        p.centre_m.push_back(tube.point_at(s) + wa * a + wb * b);
    }
    return p;
}

}  // namespace tridex::app::study
