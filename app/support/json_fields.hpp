// app/support/json_fields.hpp - reading one JSON object of a scene file field by field, every value checked, and refusing
// the fields nobody asked for; every message names the file and the field.
#pragma once

#include <cmath>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/format.hpp"
#include "core/math.hpp"
#include "core/text/printable.hpp"

namespace tridex::app {

/// The fields of one JSON object of a scene file (`source`), read by name; `prefix` is the object's own path
/// ("tool", "objects[0]"; "" for the top level). Every reader throws tridex::Error "<source>: field '<prefix.name>':
/// <what is wrong>" for a wrong type or an out-of-range value; finish() refuses the names nobody asked for. The JSON
/// must outlive the Fields.
class Fields {
public:
    using json = nlohmann::json;

    Fields(const json& j, const std::string& source, const std::string& prefix)
        : j_(j), source_(source), prefix_(prefix) {
        if (!j.is_object()) fail(prefix_.empty() ? "(top level)" : prefix_, "must be a JSON object");
    }

    /// Throws tridex::Error "<source>: field '<field>': <what>"; a field path or reason that quotes the file's
    /// text (a key, a name) is made printable (core/text/printable.hpp), so the message stays one line.
    [[noreturn]] void fail(const std::string& field, const std::string& what) const {
        throw Error(source_ + ": field '" + printable(field, 120) + "': " + printable(what, 400));
    }
    std::string path(const std::string& name) const { return prefix_.empty() ? name : prefix_ + "." + name; }

    const json* get(const std::string& name) {
        known_.insert(name);
        const auto it = j_.find(name);
        return it == j_.end() ? nullptr : &*it;
    }

    double number(const std::string& name, double def, double lo, double hi, bool lo_open = false) {
        const json* v = get(name);
        if (!v) return def;
        if (!v->is_number()) fail(path(name), "must be a number");
        const double x = v->get<double>();
        if (!std::isfinite(x) || x > hi || (lo_open ? x <= lo : x < lo))
            fail(path(name), "must be in " + std::string(lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) + "], got " +
                                 format_number(x));
        return x;
    }

    int integer(const std::string& name, int def, int lo, int hi) {
        const json* v = get(name);
        if (!v) return def;
        if (!v->is_number_integer()) fail(path(name), "must be an integer");
        const long long x = v->get<long long>();
        if (x < lo || x > hi)
            fail(path(name), "must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " +
                                 std::to_string(x));
        return static_cast<int>(x);
    }

    bool boolean(const std::string& name, bool def) {
        const json* v = get(name);
        if (!v) return def;
        if (!v->is_boolean()) fail(path(name), "must be true or false");
        return v->get<bool>();
    }

    std::string text(const std::string& name, const std::string& def) {
        const json* v = get(name);
        if (!v) return def;
        if (!v->is_string()) fail(path(name), "must be a string");
        return v->get<std::string>();
    }

    Vec3 vec3(const std::string& name, const Vec3& def) {
        const json* v = get(name);
        return v ? vec3_of(*v, path(name)) : def;
    }

    Vec3 vec3_of(const json& v, const std::string& field) const {
        if (!v.is_array() || v.size() != 3) fail(field, "must be an array of 3 numbers (m)");
        Vec3 out;
        for (int k = 0; k < 3; ++k) {
            if (!v[k].is_number()) fail(field, "must be an array of 3 numbers (m)");
            out[k] = v[k].get<double>();
            if (!std::isfinite(out[k])) fail(field, "must be finite");
        }
        return out;
    }

    /// A turn given as "axis" ([x, y, z], any length but zero; default +y) and "angle_deg" (right-handed about the
    /// axis, [-360, 360]; default 0): the unit quaternion of that rotation. A zero axis fails naming "axis".
    Quat turn() {
        const Vec3 axis = vec3("axis", Vec3(0.0, 1.0, 0.0));
        const double angle = number("angle_deg", 0.0, -360.0, 360.0);
        const double len = std::sqrt(axis.x * axis.x + axis.y * axis.y + axis.z * axis.z);
        if (!(len > 1e-12)) fail(path("axis"), "must not be zero (the axis the object is turned about)");
        return glm::normalize(glm::angleAxis(glm::radians(angle), axis / len));
    }

    /// A colour field: an array of 3 or 4 numbers in [0, 1] (RGB or RGBA) into rgb and alpha; both untouched when the
    /// field is absent.
    void rgba(const std::string& name, Vec3& rgb, double& alpha) {
        const json* c = get(name);
        if (!c) return;
        if (!c->is_array() || (c->size() != 3 && c->size() != 4))
            fail(path(name), "must be an array of 3 or 4 numbers in [0, 1] (RGB or RGBA)");
        double v[4] = {0.0, 0.0, 0.0, 1.0};
        for (std::size_t k = 0; k < c->size(); ++k) {
            if (!(*c)[k].is_number()) fail(path(name), "must be an array of 3 or 4 numbers in [0, 1]");
            v[k] = (*c)[k].get<double>();
            if (!(v[k] >= 0.0 && v[k] <= 1.0))
                fail(path(name), "each component must be in [0, 1], got " + format_number(v[k]));
        }
        rgb = Vec3(v[0], v[1], v[2]);
        alpha = v[3];
    }

    void finish() const {
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (!known_.count(it.key())) fail(path(it.key()), "unknown field");
    }

    const std::string& source() const { return source_; }

private:
    const json& j_;
    std::string source_, prefix_;
    std::set<std::string> known_;
};

}  // namespace tridex::app
