// app/session/view/study_view.cpp - contact, colours and the end-cap gate of a study scene in a live run.
#include "app/session/view/study_view.hpp"

#include <cstdio>

namespace tridex::app::study {

StudyView::StudyView(const RunStudy& study)
    : study_(study), tube_(study.scene.tube), model_(study_model(study.scene, study.model, "study.model")),
      meshes_(study_object_meshes(tube_)) {
    objects_ = study_scene_objects(meshes_, model_, contact_);
}

const std::vector<renderer::SceneObject>& StudyView::frame(const haptics::LoopView& view) {
    if (view.tick > 0) {
        const Vec3 bottom = view.tool_world.position;
        const Vec3 top = bottom + view.tool_world.orientation * Vec3(0.0, study_.scene.wand_length_m, 0.0);
        contact_ = study_contact(tube_, top, bottom, 0.0);  // the god-objects' points have no ball
        ++frames_;
        tube_frames_ += contact_.tube;
        funnel_frames_ += contact_.funnels;
        start_frames_ += contact_.start_cap;
        end_frames_ += contact_.end_cap;
        if (contact_.start_cap) started_ = true;
        if (started_ && contact_.end_cap) done_ = true;
    }
    objects_ = study_scene_objects(meshes_, model_, contact_);
    return objects_;
}

std::string StudyView::status() const {
    std::string s = study_.phase_line.empty() ? "" : study_.phase_line + "\n";
    s += "study model: " + study_.model;
    // What to do next: the trial's clock runs from the start cap to the end cap, wherever the wand begins.
    s += !started_ ? "  - move the wand onto the start cap (both points)"
         : !done_  ? "  - guide the wand through to the end cap"
                   : "  - end cap reached";
    if (contact_.tube) s += "  [tube touched]";
    if (contact_.funnels) s += "  [funnel touched]";
    if (contact_.start_cap) s += "  [start cap]";
    if (contact_.end_cap) s += "  [end cap]";
    return s;
}

nlohmann::json StudyView::report_json() const {
    char id[16];
    std::snprintf(id, sizeof id, "%08x", tube_id(study_.scene.tube));
    return {{"scene", study_.scene.path},
            {"model", study_.model},
            {"tube", study_.scene.tube.name},
            {"tube_id", id},
            {"frames", frames_},
            {"frames_touching",
             {{"tube", tube_frames_}, {"funnels", funnel_frames_}, {"start_cap", start_frames_}, {"end_cap", end_frames_}}},
            {"started", started_},
            {"trial_done", done_}};
}

}  // namespace tridex::app::study
