// app/session/view/study_view.hpp - a study scene in a live `tridex run` session: per frame, which objects the wand
// touches, the objects drawn in their colours, the overlay line, and the end-cap gate of a test trial.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/scene/run_scene.hpp"
#include "app/scene/study_objects.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app::study {

/// The render thread's side of a study run (RunStudy): builds the object meshes once, then per frame turns the
/// haptic loop's newest tool pose into the wand's two points (bottom = the tool centre, the flat end; top =
/// wand_length_m along the tool's +y), their contact (study_contact of the two points, as the god-objects and
/// the analysis take them: without a ball) and the objects'
/// colours. Counts frames with each contact and gates a test trial: it is done once both points touched the end
/// cap after both touched the start cap. One thread.
class StudyView {
public:
    /// Throws tridex::Error as Tube and study_model do for a bad study (RunStudy::enabled must be true).
    explicit StudyView(const RunStudy& study);

    /// Updates the contact from `view` (nothing before the loop's first tick) and returns the visible objects
    /// with this frame's colours (valid until the next call).
    const std::vector<renderer::SceneObject>& frame(const haptics::LoopView& view);
    /// The overlay line: the phase line (when set), the model, and what the wand touches now.
    std::string status() const;
    /// True once both points touched the end cap after both had touched the start cap.
    bool trial_done() const { return done_; }
    /// True once both points touched the start cap.
    bool started() const { return started_; }
    /// The contact of the last frame.
    const StudyContact& contact() const { return contact_; }
    /// report.json `study`: {scene, model, tube, frames, frames_touching {tube, funnels, start_cap, end_cap},
    /// started, trial_done}.
    nlohmann::json report_json() const;

private:
    const RunStudy& study_;
    Tube tube_;
    const StudyModel& model_;
    StudyObjectMeshes meshes_;
    std::vector<renderer::SceneObject> objects_;
    StudyContact contact_;
    bool started_ = false, done_ = false;
    std::size_t frames_ = 0, tube_frames_ = 0, funnel_frames_ = 0, start_frames_ = 0, end_frames_ = 0;
};

}  // namespace tridex::app::study
