// app/scene/scene_materials.hpp - a scene's "materials" (the contact of each material id, and the names and sRGB
// colours people paint with) and its "material" (the one union adds and paint sets, by id or by name).
#pragma once

#include "app/scene/session_spec.hpp"
#include "app/support/json_fields.hpp"

namespace tridex::app {

/// Reads the top level's "materials" array into spec.materials (contact) and spec.palette (names and colours), then
/// its "material" (an id 1..kMaxMaterialId or a palette name) into spec.material. An entry:
/// {"id": 0..255, "name": "teal", "colour": "#2a9d8f" | [42, 157, 143], "stiffness_n_per_m": ..., ...}; a name or a
/// colour needs an id 0..kMaxMaterialId, a colour needs a name, a name must be unique in the palette (the default
/// names of entries not renamed included). An entry with contact fields, or with neither a name nor a colour, is a
/// contact entry (ids not listed use the tool's contact). Throws tridex::Error "<scene>: field 'materials[2].colour':
/// must be \"#rrggbb\" or [r, g, b] with 0..255 (sRGB), got \"#12\"" and the like.
void read_scene_materials(Fields& top, SessionSpec& spec);

}  // namespace tridex::app
