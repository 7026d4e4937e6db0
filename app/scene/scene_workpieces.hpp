// app/scene/scene_workpieces.hpp - a scene's workpiece ("workpiece") or workpieces ("workpieces"): a mesh or a saved
// model each, its lattice and where it stands.
#pragma once

#include <string>

#include "app/scene/session_spec.hpp"
#include "app/support/json_fields.hpp"

namespace tridex::app {

/// Reads the top level's "workpiece" (one object) or "workpieces" (an array of 1..haptics::kMaxLoopWorkpieces such
/// objects; not both) into spec: the first into spec's own workpiece fields, the others into spec.more_workpieces.
/// An object: {"mesh": FILE (relative to base_dir; default the bundled bunny), "resolution", "stock_m", "centre_m",
/// "axis", "angle_deg"} or {"model": FILE.tdx, "position_m", "axis", "angle_deg"}. A model names the scene's palette
/// when the scene renames or recolours materials (`names_materials`), from the first workpiece's model. Neither field:
/// the bundled bunny. Throws tridex::Error "<scene>: field 'workpieces[1].mesh': no such file: ..." and the like.
void read_scene_workpieces(Fields& top, SessionSpec& spec, const std::string& base_dir, bool names_materials);

}  // namespace tridex::app
