// haptics/elastic_object.cpp - contacts, force and drawn deformation of an elastic sphere.
#include "haptics/elastic_object.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/format.hpp"
#include "haptics/forces/force_clamp.hpp"

namespace tridex::haptics {

void validate(const ElasticSphere& s, const std::string& what) {
    auto bad = [&](const char* field, const std::string& why) {
        throw Error(what + ": field '" + field + "': " + why);
    };
    if (!is_finite(s.centre_m)) bad("centre_m", "must be finite");
    if (!(std::isfinite(s.radius_m) && s.radius_m > 0.0 && s.radius_m <= 10.0))
        bad("radius_m", "must be in (0, 10] m, got " + format_number(s.radius_m));
    if (!(std::isfinite(s.stiffness_n_per_m) && s.stiffness_n_per_m > 0.0 && s.stiffness_n_per_m <= 1e5))
        bad("stiffness_n_per_m", "must be in (0, 100000] N/m, got " + format_number(s.stiffness_n_per_m));
    if (!(std::isfinite(s.influence_m) && s.influence_m > 0.0 && s.influence_m <= s.radius_m))
        bad("influence_radius_m", "must be in (0, radius_m = " + format_number(s.radius_m) + "] m, got " +
                                      format_number(s.influence_m));
}

double ElasticContacts::max_depth_m() const {
    double d = 0.0;
    for (int i = 0; i < count; ++i) d = std::max(d, contact[i].depth_m);
    return d;
}

ElasticContacts elastic_contacts(const ElasticSphere& sphere, const ToolPoints& points, const Pose& tool_world) {
    ElasticContacts out;
    if (!is_finite(tool_world.position) || !std::isfinite(tool_world.orientation.w) ||
        !std::isfinite(tool_world.orientation.x) || !std::isfinite(tool_world.orientation.y) ||
        !std::isfinite(tool_world.orientation.z))
        return out;
    const int n = std::clamp(points.count, 0, kMaxToolPoints);
    for (int i = 0; i < n; ++i) {
        const Vec3 p = tool_point_world(tool_world, points.local_m[i]);
        const Vec3 r = p - sphere.centre_m;
        const double len = glm::length(r);
        const double depth = sphere.radius_m + points.radius_m - len;
        if (!(depth > 0.0)) continue;
        ElasticContact& c = out.contact[out.count++];
        c.normal = len > 0.0 ? r / len : Vec3(0.0, 1.0, 0.0);
        c.surface_m = sphere.centre_m + sphere.radius_m * c.normal;
        c.depth_m = depth;
    }
    return out;
}

Vec3 penetration_force(double stiffness_n_per_m, const ElasticContacts& contacts, double max_force_n) {
    if (!(std::isfinite(max_force_n) && max_force_n > 0.0)) return Vec3(0.0);
    Vec3 normal(0.0);
    double deepest = 0.0;
    for (int i = 0; i < contacts.count; ++i) {
        const ElasticContact& c = contacts.contact[i];
        normal += c.depth_m * c.normal;  // Popescu 3.2: depth-weighted normals of the points in contact
        deepest = std::max(deepest, c.depth_m);
    }
    const double len = glm::length(normal);
    if (!(len > 0.0) || !std::isfinite(len)) return Vec3(0.0);
    const Vec3 f = (stiffness_n_per_m * deepest / len) * normal;
    if (!is_finite(f)) return Vec3(0.0);
    return clamp_force(f, max_force_n);
}

Vec3 elastic_force(const ElasticSphere& sphere, const ElasticContacts& contacts, double max_force_n) {
    return penetration_force(sphere.stiffness_n_per_m, contacts, max_force_n);
}

void deform_elastic_mesh(const TriMesh& reference, const ElasticContacts& contacts, double influence_m,
                         TriMesh& deformed) {
    deformed.positions.resize(reference.positions.size());
    if (deformed.triangles.size() != reference.triangles.size()) deformed.triangles = reference.triangles;
    const double r2 = influence_m * influence_m;
    for (std::size_t v = 0; v < reference.positions.size(); ++v) {
        const Vec3& q = reference.positions[v];
        double best = 0.0;
        int who = -1;
        for (int i = 0; i < contacts.count; ++i) {
            const ElasticContact& c = contacts.contact[i];
            const Vec3 e = q - c.surface_m;
            const double d2 = glm::dot(e, e);
            if (!(d2 < r2)) continue;
            const double amount = c.depth_m * (1.0 - d2 / r2);  // Popescu 3.3: k = 1 - (d/r)^2
            if (amount > best) best = amount, who = i;
        }
        deformed.positions[v] = who < 0 ? q : q - best * contacts.contact[who].normal;
    }
}

double max_vertex_displacement_m(const TriMesh& a, const TriMesh& b) {
    if (a.positions.size() != b.positions.size())
        throw Error("max_vertex_displacement_m: the meshes have " + std::to_string(a.positions.size()) + " and " +
                    std::to_string(b.positions.size()) + " vertices");
    double m = 0.0;
    for (std::size_t i = 0; i < a.positions.size(); ++i) m = std::max(m, glm::length(a.positions[i] - b.positions[i]));
    return m;
}

}  // namespace tridex::haptics
