// app/commands/export/export.cpp - saved model -> CPU contour -> STL / OBJ / PLY.
#include "app/commands/export/export.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "app/support/memory.hpp"
#include "app/support/output_dir.hpp"
#include "app/support/progress.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/mesh_obj_mtl.hpp"
#include "compute/mesh/mesh_write.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"

namespace tridex::app {

ExportResult run_export(const ExportOptions& o) {
    double scale = 1.0;
    if (o.units == "mm") scale = 1e3;
    else if (o.units == "in") scale = 1.0 / 0.0254;  // the international inch, 25.4 mm exactly
    else if (o.units != "m") throw Error("--units: must be m, mm or in, got '" + o.units + "'");
    if (o.frame != "world" && o.frame != "input") throw Error("--frame: must be world or input, got '" + o.frame + "'");
    if (o.frame == "input" && o.units != "m")
        throw Error("--units " + o.units + ", --frame input: the input frame keeps the input mesh's own units; choose one");
    const compute::MeshFileFormat format = compute::mesh_file_format(o.out);  // refuse .xyz before the slow work
    check_output_file(o.out, "OUT");
    if (format == compute::MeshFileFormat::kObj) check_output_file(compute::mtl_path_for(o.out), "OUT's material library");
    compute::TdxModel saved;
    {
        ProgressReporter::Step step = progress().step("loading " + o.model);
        saved = compute::load_tdx(o.model, model_memory_budget_bytes(), step.fn());
    }
    compute::TriDexel& model = saved.model;
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
    compute::Contourer contourer(model);
    TriMesh mesh;
    {
        ProgressReporter::Step step = progress().step("contouring the model");
        contourer.update(model, step.fn());
        mesh = contourer.mesh();
    }
    const std::vector<std::uint8_t> materials = contourer.mesh_materials();

    ExportResult r;
    r.volume_dexel_m3 = compute::dexel_volume_m3(model);
    r.volume_mesh_m3 = signed_volume(mesh);
    r.vertices = mesh.positions.size();
    r.triangles = mesh.triangles.size();
    r.boundary_edges = edge_stats(mesh).boundary_edges;
    if (r.triangles == 0) throw Error(o.model + ": the model is empty; nothing to export");
    if (o.frame == "input") {  // world m -> the input mesh's frame: the inverse of the model's placement
        const Mat4 from_world = glm::inverse(saved.to_world);
        for (Vec3& p : mesh.positions) p = Vec3(from_world * glm::dvec4(p, 1.0));
    } else {
        for (Vec3& p : mesh.positions) p *= scale;
    }
    std::vector<std::array<std::uint8_t, 3>> colours;  // PLY: the palette's sRGB colour of each vertex's material
    if (format == compute::MeshFileFormat::kPly) {
        colours.reserve(materials.size());
        for (std::uint8_t m : materials) colours.push_back(srgb8(saved.palette[m]));
    }
    {
        ProgressReporter::Step step = progress().step("writing " + o.out);
        if (format == compute::MeshFileFormat::kObj)  // OBJ + a material library named from the palette
            compute::write_obj_with_materials(o.out, mesh, materials, saved.palette);
        else
            compute::write_mesh_file(o.out, mesh, colours);
    }
    std::printf("tridex export: %s -> %s (%zu vertices, %zu triangles, %s; volume %.6g m^3, tri-dexel %.6g m^3)\n",
                o.model.c_str(), o.out.c_str(), r.vertices, r.triangles,
                o.frame == "input" ? "the input mesh's frame and units"
                : o.units == "mm"  ? "millimetres"
                : o.units == "in"  ? "inches"
                                   : "metres",
                r.volume_mesh_m3, r.volume_dexel_m3);
    return r;
}

}  // namespace tridex::app
