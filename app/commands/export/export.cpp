// app/commands/export/export.cpp - saved model or scene -> CPU contour -> placed in the world -> STL / OBJ / PLY.
#include "app/commands/export/export.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <vector>

#include "app/scene/reference_objects.hpp"
#include "app/scene/run_scene.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/scene/workpiece_source.hpp"
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

namespace {

// What is exported: the workpiece's model with its placement, palette and pose, and a scene's reference objects.
struct ExportSource {
    compute::TriDexel model;
    Mat4 to_world{1.0};  // input mesh units -> world m (the model frame)
    MaterialPalette palette = default_material_palette();
    Pose pose{};  // the model frame -> the world (a scene's workpiece pose)
    std::vector<ReferenceSpec> references;
    // A scene's further workpieces: each model, its placement and pose, as the first's.
    struct More {
        compute::TriDexel model;
        Mat4 to_world{1.0};
        Pose pose{};
    };
    std::vector<More> more;
};

// A model contoured whole on the CPU (as a session's final mesh) and moved into the frame asked for: the world by its
// pose, scaled to the units, or back into its input mesh's frame.
struct Contoured {
    TriMesh mesh;
    std::vector<std::uint8_t> materials;
    double volume_dexel_m3 = 0.0;
    double volume_mesh_m3 = 0.0;  // of the mesh before it was moved or scaled, m^3
};

Contoured contour_placed(compute::TriDexel& model, const Pose& pose, const Mat4& to_world, bool input_frame,
                         double scale, const std::string& what) {
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});
    compute::Contourer contourer(model);
    Contoured c;
    {
        ProgressReporter::Step step = progress().step("contouring " + what);
        contourer.update(model, step.fn());
        c.mesh = contourer.mesh();
    }
    c.materials = contourer.mesh_materials();
    c.volume_dexel_m3 = compute::dexel_volume_m3(model);
    c.volume_mesh_m3 = signed_volume(c.mesh);
    if (input_frame) {  // the model frame -> the input mesh's frame: the inverse of the model's placement
        const Mat4 from_world = glm::inverse(to_world);
        for (Vec3& p : c.mesh.positions) p = Vec3(from_world * glm::dvec4(p, 1.0));
    } else {
        for (Vec3& p : c.mesh.positions) p = scale * pose.apply(p);
    }
    return c;
}

bool is_scene_file(const std::string& path) {
    return path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
}

ExportSource load_source(const std::string& path) {
    ExportSource src;
    if (!is_scene_file(path)) {
        ProgressReporter::Step step = progress().step("loading " + path);
        compute::TdxModel saved = compute::load_tdx(path, model_memory_budget_bytes(), step.fn());
        src.model = std::move(saved.model);
        src.to_world = saved.to_world;
        src.palette = saved.palette;
        return src;
    }
    RunScene scene = load_run_scene(path);
    if (scene.study.enabled) throw Error(path + ": a study scene has no workpiece to export");
    SessionSpec& spec = scene.spec;
    Workpiece wp = prepare_session_workpiece(spec);  // a saved model loaded, or the mesh scan-converted
    src.model = std::move(wp.model);
    src.to_world = wp.to_world;
    src.palette = spec.palette;
    src.pose = workpiece_pose(spec);
    src.references = spec.references;
    std::vector<Workpiece> more = prepare_more_workpieces(spec);
    for (std::size_t k = 1; k <= more.size(); ++k)
        src.more.push_back({std::move(more[k - 1].model), more[k - 1].to_world, workpiece_pose(spec_for_workpiece(spec, k))});
    return src;
}

// A reference's mesh in the world, m (its own-frame mesh placed by its pose, as the session draws it).
TriMesh reference_in_world(const ReferenceSpec& r) {
    TriMesh mesh = load_reference_mesh(r);
    const Pose pose{r.position_m, r.orientation};
    for (Vec3& p : mesh.positions) p = pose.apply(p);
    return mesh;
}

// "ref_<name>" with every byte a material name may not hold replaced by '_', at most kMaterialNameMax bytes.
std::string reference_material_name(const std::string& name) {
    std::string out = "ref_" + name;
    for (char& c : out)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
    return out.substr(0, kMaterialNameMax);
}

// The workpieces ("workpiece", "workpiece_2", ...) and the references as OBJ objects, one material per palette entry
// and one per reference.
void write_obj(const std::string& out, const std::vector<Contoured>& pieces, const MaterialPalette& palette,
               const std::vector<ReferenceSpec>& refs, const std::vector<TriMesh>& ref_meshes) {
    if (refs.empty() && pieces.size() == 1)
        return compute::write_obj_with_materials(out, pieces[0].mesh, pieces[0].materials, palette);
    std::vector<compute::ObjMaterial> lib;
    for (const PaletteEntry& e : palette.entries) lib.push_back({e.name, e.rgb});
    std::vector<compute::ObjObject> objects;
    for (std::size_t k = 0; k < pieces.size(); ++k) {
        const std::vector<std::uint8_t> tri = compute::triangle_materials(pieces[k].mesh, pieces[k].materials);
        objects.push_back({k == 0 ? std::string("workpiece") : "workpiece_" + std::to_string(k + 1), &pieces[k].mesh,
                           std::vector<std::uint16_t>(tri.begin(), tri.end())});
    }
    for (std::size_t i = 0; i < refs.size(); ++i) {
        std::string name = reference_material_name(refs[i].name);
        for (int k = 2; std::any_of(lib.begin(), lib.end(), [&](const auto& m) { return m.name == name; }); ++k)
            name = reference_material_name(refs[i].name).substr(0, kMaterialNameMax - 3) + "_" + std::to_string(k);
        lib.push_back({name, {static_cast<float>(refs[i].colour.x), static_cast<float>(refs[i].colour.y),
                              static_cast<float>(refs[i].colour.z)}});
        objects.push_back({name, &ref_meshes[i],
                           std::vector<std::uint16_t>(ref_meshes[i].triangles.size(),
                                                      static_cast<std::uint16_t>(lib.size() - 1))});
    }
    compute::write_obj_objects(out, objects, lib);
}

// `extra` appended to `mesh` (its indices moved past mesh's vertices).
void append_mesh(TriMesh& mesh, const TriMesh& extra) {
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), extra.positions.begin(), extra.positions.end());
    for (auto t : extra.triangles) mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// `pieces` (and, with `refs`, the references) in one file: an OBJ object each, or one STL or PLY mesh (PLY vertices in
// their material's palette colour, each reference's in its own).
void write_pieces(const std::string& out, compute::MeshFileFormat format, const std::vector<Contoured>& pieces,
                  const MaterialPalette& palette, const std::vector<ReferenceSpec>& refs,
                  const std::vector<TriMesh>& ref_meshes) {
    if (format == compute::MeshFileFormat::kObj) return write_obj(out, pieces, palette, refs, ref_meshes);
    TriMesh mesh;
    std::vector<std::array<std::uint8_t, 3>> colours;
    const bool ply = format == compute::MeshFileFormat::kPly;
    for (const Contoured& c : pieces) {
        append_mesh(mesh, c.mesh);
        if (ply)
            for (std::uint8_t m : c.materials) colours.push_back(srgb8(palette[m]));
    }
    for (std::size_t i = 0; i < refs.size(); ++i) {
        append_mesh(mesh, ref_meshes[i]);
        const Vec3& c = refs[i].colour;
        if (ply)
            colours.insert(colours.end(), ref_meshes[i].positions.size(),
                           {to_byte(static_cast<float>(c.x)), to_byte(static_cast<float>(c.y)),
                            to_byte(static_cast<float>(c.z))});
    }
    compute::write_mesh_file(out, mesh, colours);
}

}  // namespace

ExportResult run_export(const ExportOptions& o) {
    double scale = 1.0;
    if (o.units == "mm") scale = 1e3;
    else if (o.units == "in") scale = 1.0 / 0.0254;  // the international inch, 25.4 mm exactly
    else if (o.units != "m") throw Error("--units: must be m, mm or in, got '" + o.units + "'");
    if (o.frame != "world" && o.frame != "input") throw Error("--frame: must be world or input, got '" + o.frame + "'");
    if (o.objects != "workpiece" && o.objects != "all")
        throw Error("--objects: must be workpiece or all, got '" + o.objects + "'");
    if (o.frame == "input" && o.units != "m")
        throw Error("--units " + o.units + ", --frame input: the input frame keeps the input mesh's own units; choose one");
    const bool all = o.objects == "all";
    if (all && !is_scene_file(o.model))
        throw Error("--objects all: " + o.model + " is a model file, which holds the workpiece alone; give the scene "
                    "(a .json, such as the .scene.json a session saves beside its model)");
    if (all && o.frame == "input")
        throw Error("--objects all, --frame input: the input frame is the workpiece's own mesh's; the objects beside it "
                    "are placed in the world");
    const compute::MeshFileFormat format = compute::mesh_file_format(o.out);  // refuse .xyz before the slow work
    check_output_file(o.out, "OUT");
    if (format == compute::MeshFileFormat::kObj) check_output_file(compute::mtl_path_for(o.out), "OUT's material library");
    ExportSource src = load_source(o.model);
    const bool input = o.frame == "input";
    std::vector<Contoured> pieces;
    pieces.push_back(contour_placed(src.model, src.pose, src.to_world, input, scale, "the model"));
    for (std::size_t k = 0; k < src.more.size(); ++k)
        pieces.push_back(contour_placed(src.more[k].model, src.more[k].pose, src.more[k].to_world, input, scale,
                                        "workpiece " + std::to_string(k + 2)));
    ExportResult r;
    const TriMesh& first = pieces[0].mesh;
    r.volume_dexel_m3 = pieces[0].volume_dexel_m3;
    r.volume_mesh_m3 = pieces[0].volume_mesh_m3;
    r.vertices = first.positions.size();
    r.triangles = first.triangles.size();
    r.boundary_edges = edge_stats(first).boundary_edges;
    r.workpieces = pieces.size();
    if (r.triangles == 0) throw Error(o.model + ": the model is empty; nothing to export");
    // Each further workpiece in a file of its own beside OUT, unless all go in one.
    std::vector<std::string> files{o.out};
    for (std::size_t k = 1; k < pieces.size() && !all; ++k) {
        files.push_back(path_for_workpiece(o.out, k));
        check_output_file(files.back(), "OUT's workpiece " + std::to_string(k + 1));
        if (format == compute::MeshFileFormat::kObj)
            check_output_file(compute::mtl_path_for(files.back()), "OUT's workpiece " + std::to_string(k + 1) + "'s materials");
    }
    std::vector<ReferenceSpec> refs = all ? src.references : std::vector<ReferenceSpec>{};
    std::vector<TriMesh> ref_meshes;
    for (const ReferenceSpec& ref : refs) {
        ProgressReporter::Step step = progress().step("loading reference '" + ref.name + "'");
        ref_meshes.push_back(reference_in_world(ref));
        for (Vec3& p : ref_meshes.back().positions) p *= scale;
    }
    r.references = refs.size();
    for (std::size_t f = 0; f < files.size(); ++f) {
        ProgressReporter::Step step = progress().step("writing " + files[f]);
        const std::vector<Contoured> in_file =
            all ? std::move(pieces) : std::vector<Contoured>{std::move(pieces[f])};
        write_pieces(files[f], format, in_file, src.palette, f == 0 ? refs : std::vector<ReferenceSpec>{}, ref_meshes);
    }
    const bool posed = !src.pose.is_identity() && o.frame == "world";
    std::printf("tridex export: %s -> %s (%zu vertices, %zu triangles, %s%s; volume %.6g m^3, tri-dexel %.6g m^3)%s%s\n",
                o.model.c_str(), o.out.c_str(), r.vertices, r.triangles,
                o.frame == "input" ? "the input mesh's frame and units"
                : o.units == "mm"  ? "millimetres"
                : o.units == "in"  ? "inches"
                                   : "metres",
                posed ? ", placed by the scene's pose" : "", r.volume_mesh_m3, r.volume_dexel_m3,
                refs.empty() ? "" : (" and " + std::to_string(refs.size()) + " reference object(s)").c_str(),
                r.workpieces < 2 ? ""
                : all            ? (" and " + std::to_string(r.workpieces - 1) + " more workpiece(s)").c_str()
                                 : (", and " + std::to_string(r.workpieces - 1) + " more workpiece(s) beside it (" +
                                    files[1] + (files.size() > 2 ? ", ..." : "") + ")").c_str());
    return r;
}

}  // namespace tridex::app
