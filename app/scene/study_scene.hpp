// app/scene/study_scene.hpp - a study scene file: the navigation tube, the wand, the protocol's timings and the
// three models of the thesis (Singapogu 2007, 4.2: haptic training, visual training, test).
#pragma once

#include <string>

#include "app/scene/tube.hpp"

namespace tridex::app::study {

/// How one object of a model is shown and felt (thesis 4.3.2).
struct ObjectLook {
    bool visible = true;            ///< drawn
    bool felt = true;               ///< has contact force
    bool colour_on_contact = false; ///< turns from green to red on contact (a cap: when both tool points touch it)
};

/// One model of the experiment: the tube, the funnels and the caps.
struct StudyModel {
    ObjectLook tube, funnels, caps;
};

/// The protocol's phases (thesis 4.2.2, Fig. 32, Appendix C), s of wall time.
struct ProtocolTimings {
    double introduction_s = 60.0;     ///< introduction to the device and the task
    double presentation_s = 60.0;     ///< presentation of the training model
    double test_look_s = 30.0;        ///< a look at the test model
    double training_s = 300.0;        ///< timed training
    int test_trials = 2;              ///< untimed test trials, each ended by the end cap
    double trial_timeout_s = 300.0;   ///< a test trial that has not reached the end cap by then is stopped
};

/// A study scene.
struct StudyScene {
    std::string path;                  ///< the file it was read from (absolute), or "" for the built-in default
    TubeSpec tube;
    double wand_length_m = 0.02;       ///< distance between the wand's bottom and top points, m
    double wand_radius_m = 0.003;      ///< the wand's radius (its flat end), m
    ProtocolTimings protocol;
    /// The thesis's models: haptic training (tube invisible, walls felt), visual training (tube visible, no force,
    /// colour on contact), test (no tube; funnels seen and felt; caps seen).
    StudyModel haptic_training{{false, true, false}, {true, true, false}, {true, false, true}};
    StudyModel visual_training{{true, false, true}, {true, false, true}, {true, false, true}};
    StudyModel test{{false, false, false}, {true, true, false}, {true, false, true}};
};

/// Reads a study scene file {"tube": {...}, "wand": {"length_m", "radius_m"}, "protocol": {...}, "models":
/// {"haptic_training"|"visual_training"|"test": {"tube"|"funnels"|"caps": {"visible", "felt",
/// "colour_on_contact"}}}}; everything but "tube" optional. Throws tridex::Error "<path>: field '<a.b>': ..."
/// for an unreadable file, bad JSON, an unknown, missing, ill-typed or out-of-range field.
StudyScene read_study_scene(const std::string& path);

/// The bundled scene: assets/study_tube_scene.json (tridex's asset folder). Throws as read_study_scene.
std::string default_study_scene_path();

}  // namespace tridex::app::study
