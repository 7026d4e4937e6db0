// app/scene/tool_mesh.hpp - a session's mesh tool from its file: loaded, sized, placed on its reference point.
#pragma once

#include <memory>
#include <string>

#include "compute/tools/mesh_tool.hpp"
#include "core/tri_mesh.hpp"

namespace tridex::app {

/// Loads a closed tool mesh for a session (compute::load_closed_mesh: closed, manifold, consistently
/// oriented, non-zero volume) and puts it in the tool frame of core/tool_shape.hpp, m: scaled uniformly so
/// that the longest side of its bounding box is size_m (m, > 0), and moved so that its reference point, the
/// tool tip, is the origin. The tip is where a CAD or Freeform user holds a tool: the centre of the bounding
/// box across the axis (x, z) at its lowest point along the axis (-y), like a flat-end mill's end face; the
/// file's +y is the tool axis, pointing from the tip toward the hand. Throws tridex::Error "<path>: ..." as
/// load_closed_mesh does, or when size_m is not finite and > 0.
TriMesh load_tool_mesh(const std::string& path, double size_m);

/// The mesh tool of load_tool_mesh(path, size_m) for the Booleans (compute::MeshTool::create, k = 4 tool rays
/// per workpiece cell). Its mesh() is the checked tool-frame mesh the contact points and the renderer use.
/// Throws tridex::Error "<path>: ..." as load_tool_mesh, or as MeshTool::create.
std::shared_ptr<const compute::MeshTool> make_session_mesh_tool(const std::string& path, double size_m);

/// How far the tool mesh (tool frame, m) reaches below its origin along -axis (axis 0, 1, 2 = x, y, z):
/// -min over vertices of p[axis], at least 0. A stroke pressing the tool (unturned) against a face
/// perpendicular to `axis` keeps that point depth_m below the surface (app/scene/stroke.hpp tool_radius_m).
double tool_mesh_reach_m(const TriMesh& mesh_m, int axis);

}  // namespace tridex::app
