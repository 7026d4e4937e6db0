// app/scene/scene_workpieces.cpp - reading a scene's workpiece or workpieces.
#include "app/scene/scene_workpieces.hpp"

#include <cmath>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/scene/workpiece_list.hpp"
#include "app/support/assets.hpp"
#include "compute/model/tdx_file.hpp"
#include "core/format.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string default_mesh() { return fs::absolute(default_mesh_path()).lexically_normal().string(); }

// The lattice holds depths as floats from a local origin: a workpiece stays within 1 km of the origin.
void check_within_reach(const Fields& f, const std::string& name, const Vec3& p) {
    for (int a = 0; a < 3; ++a)
        if (!(std::abs(p[a]) <= 1e3))
            f.fail(f.path(name), "must lie within 1 km of the origin on every axis, got " + format_number(p[a]) +
                                     " m on axis " + "xyz"[a]);
}

fs::path scene_file(const Fields& f, const std::string& name, const std::string& file, const std::string& base_dir) {
    const fs::path p = fs::path(file).is_absolute() ? fs::path(file) : fs::path(base_dir) / file;
    if (fs::is_directory(p)) f.fail(f.path(name), "is a folder, not a file: " + p.string());
    if (!fs::is_regular_file(p)) f.fail(f.path(name), "no such file: " + p.string());
    return fs::absolute(p).lexically_normal();  // a recording replays from any folder
}

// One workpiece object; `defaults` holds the values of the fields it leaves out.
WorkpieceSpec read_one(Fields& f, const std::string& base_dir, const WorkpieceSpec& defaults) {
    WorkpieceSpec w = defaults;
    const std::string model = f.text("model", "");
    if (!model.empty()) {  // a saved model decides the lattice, the placement and the resolution
        for (const char* other : {"mesh", "resolution", "stock_m", "centre_m"})
            if (f.get(other)) f.fail(f.path(other), "not with " + f.path("model") + " (the saved model decides it)");
        w.model_path = scene_file(f, "model", model, base_dir).string();
        w.mesh_path.clear();
        // Where the saved model's centre goes (default: where it was saved), relative to the centre it was saved at
        // (only known once the model is loaded: workpiece_pose() turns about that centre).
        if (f.get("position_m")) {
            w.position_m = f.vec3("position_m", Vec3(0.0));
            check_within_reach(f, "position_m", *w.position_m);
        }
        w.turn = f.turn();
        f.finish();
        return w;
    }
    const std::string mesh = f.text("mesh", "");
    w.mesh_path = mesh.empty() ? default_mesh() : scene_file(f, "mesh", mesh, base_dir).string();
    w.resolution = f.integer("resolution", w.resolution, 8, 4096);
    w.stock_m = f.number("stock_m", w.stock_m, 0.001, 100.0);  // validate_spec's range
    w.centre_m = f.vec3("centre_m", w.centre_m);
    check_within_reach(f, "centre_m", w.centre_m);
    if (f.get("position_m")) f.fail(f.path("position_m"), "only with " + f.path("model") + " (a mesh is placed by centre_m)");
    w.turn = f.turn();
    f.finish();
    return w;
}

}  // namespace

void read_scene_workpieces(Fields& top, SessionSpec& sp, const std::string& base_dir, bool names_materials) {
    const WorkpieceSpec defaults = workpiece_at(sp, 0);
    const json* one = top.get("workpiece");
    const json* many = top.get("workpieces");
    if (one && many) top.fail("workpieces", "not with \"workpiece\": list every workpiece in \"workpieces\"");
    sp.more_workpieces.clear();
    if (!one && !many) {
        sp.mesh_path = default_mesh();
        return;
    }
    std::vector<WorkpieceSpec> list;
    if (one) {
        Fields f(*one, top.source(), "workpiece");
        list.push_back(read_one(f, base_dir, defaults));
    } else {
        if (!many->is_array() || many->empty() || many->size() > haptics::kMaxLoopWorkpieces)
            top.fail("workpieces", "must be an array of 1 to " + std::to_string(haptics::kMaxLoopWorkpieces) +
                                       " workpiece objects");
        for (std::size_t k = 0; k < many->size(); ++k) {
            Fields f((*many)[k], top.source(), "workpieces[" + std::to_string(k) + "]");
            list.push_back(read_one(f, base_dir, defaults));
        }
    }
    set_first_workpiece(sp, list.front());
    sp.more_workpieces.assign(list.begin() + 1, list.end());
    // The first model's names and colours, when the scene renames, recolours or names them (else the session takes
    // them from the model it loads: prepare_session_workpiece).
    if (!sp.model_path.empty() && names_materials) {
        try {
            sp.palette = compute::load_tdx_palette(sp.model_path);
        } catch (const Error& e) {
            top.fail(one ? "workpiece.model" : "workpieces[0].model", e.what());
        }
    }
}

}  // namespace tridex::app
