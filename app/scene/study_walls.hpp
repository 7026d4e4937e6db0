// app/scene/study_walls.hpp - the felt objects of a study model as a tri-dexel solid, so the session's
// multi-point god-object (haptics/multipoint.hpp) feels their walls through the active surface like any
// workpiece (Singapogu 2007, 4.3.2: the tube's and funnels' walls felt, each model choosing which).
#pragma once

#include <string>

#include "app/scene/workpiece_source.hpp"
#include "app/scene/study_scene.hpp"
#include "app/scene/tube.hpp"

namespace tridex::app::study {

/// How the felt walls are built.
struct WallOptions {
    double wall_m = 0.008;   ///< wall thickness around the passage, m, [2 cells, 0.1 m]
    double cell_m = 0.002;   ///< lattice spacing, m, (0, radius_m / 4]
};

/// The felt objects of `model` as a solid around the passage: for each felt object (tube: 0 <= s <= length;
/// funnels: the funnel_length_m before and after it), disks across the spine (flat-end cylinders one cell thick,
/// half a cell apart) of the passage radius plus wall_m are added, then disks of the passage radius
/// (Tube::passage_radius_m: the tube's radius, growing linearly over the funnels to half the mouth, so a funnel's
/// square section is felt as its inscribed circle) along the whole extended spine are removed; felt caps are
/// added last as disks of diameter cap_size_m and thickness cap_thickness_m across the spine. The lattice covers the tube's
/// objects with wall and margin whatever is felt (a model that feels nothing gives an empty solid there).
/// mesh_path = `source`, to_world = identity, volume_mesh_m3 = volume_dexel_m3 = the solid's dexel volume,
/// resolution = the lattice's longest side in cells. Throws tridex::Error naming the option out of range or a
/// lattice that would not fit model_memory_budget_bytes().
Workpiece felt_walls(const Tube& tube, const StudyModel& model, const std::string& source, const WallOptions& o = {});

}  // namespace tridex::app::study
