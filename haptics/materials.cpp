// haptics/materials.cpp - validation of contact materials and the per-id table.
#include "haptics/materials.hpp"

#include <cmath>

#include "core/error.hpp"

namespace tridex::haptics {

namespace {

void require_non_negative(double v, const std::string& where, const char* field) {
    if (!(std::isfinite(v) && v >= 0.0))
        throw Error(where + "." + field + " = " + std::to_string(v) + " must be finite and >= 0");
}

}  // namespace

void validate_material(const Material& m, const std::string& where) {
    require_non_negative(m.stiffness_n_per_m, where, "stiffness_n_per_m");
    require_non_negative(m.damping_n_s_per_m, where, "damping_n_s_per_m");
    require_non_negative(m.static_friction, where, "static_friction");
    require_non_negative(m.dynamic_friction, where, "dynamic_friction");
    if (m.dynamic_friction > m.static_friction)
        throw Error(where + ".dynamic_friction = " + std::to_string(m.dynamic_friction) +
                    " must not exceed static_friction = " + std::to_string(m.static_friction));
}

MaterialTable::MaterialTable(const Material& all) {
    validate_material(all, "MaterialTable");
    entries_.fill(all);
}

void MaterialTable::set(int id, const Material& m) {
    if (id < 0 || id >= kSize)
        throw Error("MaterialTable: material id " + std::to_string(id) + " is outside [0, 255]");
    validate_material(m, "MaterialTable[" + std::to_string(id) + "]");
    entries_[static_cast<std::size_t>(id)] = m;
}

}  // namespace tridex::haptics
