// app/scene/study_objects.hpp - the objects of a study scene as a live session shows them (Singapogu 2007,
// 4.2.1 and 4.3.2): triangle meshes of the tube, the funnels and the caps, which of them the wand's two points
// touch, and each object's colour in one of the three models.
#pragma once

#include <array>
#include <string>

#include "app/scene/study_scene.hpp"
#include "app/scene/tube.hpp"
#include "core/tri_mesh.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app::study {

/// The objects of a study scene, in the order of StudyObjectMeshes::all().
enum class StudyObject { kTube, kEntryFunnel, kExitFunnel, kStartCap, kEndCap };

/// "tube", "entry_funnel", "exit_funnel", "start_cap", "end_cap".
const char* to_string(StudyObject o);

/// Triangle meshes of the study objects, world m, counter-clockwise seen from outside the object's wall.
struct StudyObjectMeshes {
    TriMesh tube;          ///< the circular section of radius_m swept along the spine from s = 0 to its length (open ends)
    TriMesh entry_funnel;  ///< square sections from the mouth (side funnel_mouth_m) to 2 radius_m at the tube (open)
    TriMesh exit_funnel;   ///< the same at the exit
    TriMesh start_cap;     ///< a thin box (cap_size_m square, cap_thickness_m) at the entry mouth, across the spine
    TriMesh end_cap;       ///< the same at the exit mouth
    /// The five meshes, indexed by StudyObject.
    std::array<const TriMesh*, 5> all() const { return {&tube, &entry_funnel, &exit_funnel, &start_cap, &end_cap}; }
};

/// Builds the meshes: `sides` segments around the tube (>= 8), one ring per spine polyline sample; funnels with
/// eight sections along their length. Throws tridex::Error when sides < 8.
StudyObjectMeshes study_object_meshes(const Tube& tube, int sides = 32);

/// Which objects the wand touches, from its top and bottom points (world m).
struct StudyContact {
    bool tube = false;       ///< either point reaches the tube wall (0 <= s <= length)
    bool funnels = false;    ///< either point reaches a funnel's wall
    bool start_cap = false;  ///< both points touch the start cap (Tube::touches_start_cap)
    bool end_cap = false;    ///< both points touch the end cap
};

/// The contact of a wand whose points carry balls of point_radius_m (m, >= 0): a point touches a wall when its
/// distance from the spine plus point_radius_m reaches the passage radius there (Tube::passage_radius_m) less
/// `tolerance_m` (m, >= 0; a felt wall holds the point's god-object on it, so its HIP sits a little inside).
/// Non-finite points touch nothing.
StudyContact study_contact(const Tube& tube, const Vec3& top_m, const Vec3& bottom_m, double point_radius_m,
                           double tolerance_m = 5e-4);

/// The colour of one object in a model (linear RGBA): a colour-on-contact object is green, red while touched
/// (the tube and funnels: either point; a cap: both points, thesis 4.3.2); other visible objects keep a neutral
/// colour of their own. The tube and funnels are translucent (the wand inside stays visible), the caps nearly
/// opaque. Invisible objects get alpha 0 (callers leave them out).
glm::vec4 study_object_colour(StudyObject o, const StudyModel& model, const StudyContact& contact);

/// The model of a scene named as in a study scene file: "haptic_training", "visual_training" or "test". Throws
/// tridex::Error "<what>: model '<name>' is not one of haptic_training, visual_training, test".
const StudyModel& study_model(const StudyScene& scene, const std::string& name, const std::string& what);

/// The scene objects of one frame: the visible objects of `model` with their colours for `contact`, pointing
/// into `meshes` (which must outlive the returned objects' use).
std::vector<renderer::SceneObject> study_scene_objects(const StudyObjectMeshes& meshes, const StudyModel& model,
                                                       const StudyContact& contact);

}  // namespace tridex::app::study
