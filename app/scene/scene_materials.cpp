// app/scene/scene_materials.cpp - reading a scene's materials: contact, names and sRGB colours.
#include "app/scene/scene_materials.hpp"

#include <set>
#include <string>

#include "core/format.hpp"
#include "core/material_palette.hpp"

namespace tridex::app {

namespace {

using nlohmann::json;

constexpr const char* kColourRule = "must be \"#rrggbb\" or [r, g, b] with 0..255 (sRGB)";

std::array<std::uint8_t, 3> read_colour(const Fields& f, const json& v, const std::string& field) {
    std::array<std::uint8_t, 3> rgb{};
    if (v.is_string()) {
        if (!parse_hex_colour(v.get<std::string>(), rgb)) f.fail(field, std::string(kColourRule) + ", got \"" + v.get<std::string>() + "\"");
        return rgb;
    }
    if (!v.is_array() || v.size() != 3) f.fail(field, std::string(kColourRule) + ", got " + v.dump());
    for (int k = 0; k < 3; ++k) {
        if (!v[k].is_number_integer() || v[k].get<long long>() < 0 || v[k].get<long long>() > 255)
            f.fail(field, std::string(kColourRule) + ", got " + v.dump());
        rgb[k] = static_cast<std::uint8_t>(v[k].get<long long>());
    }
    return rgb;
}

bool has_contact(const json& entry) {
    for (const char* k : {"stiffness_n_per_m", "damping_n_s_per_m", "static_friction", "dynamic_friction"})
        if (entry.is_object() && entry.contains(k)) return true;
    return false;
}

// One entry's name and colour into the palette; `named` collects the ids renamed so far (name clashes are
// checked against the final palette by the caller).
void read_look(Fields& f, int id, SessionSpec& spec, std::set<int>& named) {
    const json* name = f.get("name");
    const json* colour = f.get("colour");
    if (!name && !colour) return;
    if (id > kMaxMaterialId)
        f.fail(f.path("id"), "a named colour needs a material id 0.." + std::to_string(kMaxMaterialId) + ", got " +
                                 std::to_string(id));
    if (!name) f.fail(f.path("colour"), "a colour needs a name (\"name\": \"teal\")");
    const std::string n = f.text("name", "");
    if (const std::string why = material_name_problem(n); !why.empty()) f.fail(f.path("name"), why);
    PaletteEntry& e = spec.palette.entries[id];
    e.name = n;
    if (colour) e.rgb = rgb_from_srgb8(read_colour(f, *colour, f.path("colour")));
    named.insert(id);
}

}  // namespace

void read_scene_materials(Fields& top, SessionSpec& spec) {
    if (const json* m = top.get("materials")) {
        if (!m->is_array()) top.fail("materials", "must be an array of {id, name, colour, stiffness_n_per_m, ...}");
        std::set<int> seen, named;
        for (std::size_t i = 0; i < m->size(); ++i) {
            Fields f((*m)[i], top.source(), "materials[" + std::to_string(i) + "]");
            if (!f.get("id")) f.fail(f.path("id"), "missing");
            const int id = f.integer("id", 0, 0, 255);
            if (!seen.insert(id).second) f.fail(f.path("id"), "material " + std::to_string(id) + " is listed twice");
            const bool look = (*m)[i].contains("name") || (*m)[i].contains("colour");
            read_look(f, id, spec, named);
            if (has_contact((*m)[i]) || !look) {
                MaterialEntry e;
                e.id = id;
                e.material.stiffness_n_per_m = f.number("stiffness_n_per_m", spec.stiffness_n_per_m, 0.0, 1e5);
                e.material.damping_n_s_per_m = f.number("damping_n_s_per_m", spec.damping_n_s_per_m, 0.0, 1e3);
                e.material.static_friction = f.number("static_friction", 0.0, 0.0, 10.0);
                e.material.dynamic_friction = f.number("dynamic_friction", 0.0, 0.0, 10.0);
                if (e.material.dynamic_friction > e.material.static_friction)
                    f.fail(f.path("dynamic_friction"),
                           "must not exceed static_friction (" + format_number(e.material.static_friction) + ")");
                spec.materials.push_back(e);
            }
            f.finish();
        }
        for (int id : named) {  // a new name must not be another entry's, renamed or default
            const int first = spec.palette.find(spec.palette.entries[id].name);
            if (first != id)
                top.fail("materials", "the name '" + spec.palette.entries[id].name + "' names materials " +
                                          std::to_string(first) + " and " + std::to_string(id) +
                                          (named.count(first) ? "" : " (" + std::to_string(first) + " by default: rename it too)"));
        }
    }
    if (const json* v = top.get("material"); v && v->is_string()) {
        const int id = spec.palette.find(v->get<std::string>());
        std::string names;
        for (int k = 1; k < kPaletteSize; ++k) names += (k > 1 ? ", " : "") + spec.palette.entries[k].name;
        if (id < 0) top.fail("material", "'" + v->get<std::string>() + "' is not a material; use " + names);
        if (id == 0) top.fail("material", "'" + v->get<std::string>() + "' is the workpiece's own material (0); use " + names);
        spec.material = id;
    } else {
        spec.material = top.integer("material", spec.material, 1, kMaxMaterialId);
    }
}

}  // namespace tridex::app
