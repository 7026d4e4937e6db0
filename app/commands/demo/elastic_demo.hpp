// app/commands/demo/elastic_demo.hpp - `tridex demo --elastic`: a scripted hand presses an elastic object in steps and lets go;
// the force comes from the undeformed reference, the drawn surface dents and springs back.
#pragma once

#include <string>
#include <vector>

#include "app/scene/elastic_scene.hpp"

namespace tridex::app {

/// Options of `tridex demo --elastic`.
struct ElasticDemoOptions {
    std::string scene;                 ///< scene file (app/scene/elastic_scene.hpp); "" = assets/squeeze_ball_scene.json
    std::string out = "out/elastic";   ///< output folder (created)
    int width = 1280;                  ///< per-eye image width, px
    int height = 960;                  ///< per-eye image height, px
    bool validate = false;             ///< enable VK_LAYER_KHRONOS_validation
};

/// One tick of the scripted press (1 kHz).
struct ElasticTick {
    double t_s = 0.0;              ///< time since the start, s
    double press_m = 0.0;          ///< how far the hand is past first contact along the press direction, m (< 0: apart)
    double penetration_m = 0.0;    ///< deepest interaction point inside the pressed object's undeformed surface, m
    Vec3 hip_m{0.0};               ///< the tool centre (HIP), world m
    Vec3 force_n{0.0};             ///< force on the hand, N (from every object, clamped to the scene's limit)
};

/// The state at the end of one hold of the press (and after the release, as the last entry).
struct ElasticStep {
    double press_m = 0.0;             ///< the hand's press depth, m (the release: -clearance)
    double penetration_m = 0.0;       ///< deepest interaction point into the undeformed surface, m
    double force_n = 0.0;             ///< |force|, N
    double max_displacement_m = 0.0;  ///< largest vertex displacement of the pressed object's drawn surface, m
};

/// What a press produced (the part of run_elastic_demo that needs no GPU).
struct ElasticPressRun {
    std::vector<ElasticTick> ticks;   ///< every tick, 1 kHz
    std::vector<ElasticStep> steps;   ///< one per depth of the press, then the release
    std::size_t deepest_tick = 0;     ///< index into ticks of the end of the deepest hold
    std::size_t deepest_step = 0;     ///< index into steps of the deepest hold
};

/// Runs the scene's press at 1 kHz without drawing: per tick the tool's interaction points against every object's
/// undeformed surface, the summed force (clamped to scene.max_force_n); at the end of each hold and after the
/// release, the pressed object's drawn surface (an icosphere of the reference, 5 subdivisions) dented by the
/// contacts. Deterministic. Throws tridex::Error for a scene that elastic_scene_from_json would refuse.
ElasticPressRun run_elastic_press(const ElasticScene& scene);

/// Runs the press, renders both eyes at the deepest hold (left.png, right.png, sbs.png) and after the release
/// (released.png, side by side), and writes haptics.csv (per tick) and report.json (`deformation`
/// {max_displacement_m, residual_displacement_m, grows_monotonically}, the steps, the force) into options.out.
/// Prints a short summary. Throws tridex::Error on a bad scene or image size, an unwritable folder, or no Vulkan
/// device.
void run_elastic_demo(const ElasticDemoOptions& options);

}  // namespace tridex::app
