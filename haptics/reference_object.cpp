// haptics/reference_object.cpp - contacts of the tool's points with a rigid object's distance field.
#include "haptics/reference_object.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::haptics {

void validate(const ReferenceObject& o, const std::string& what) {
    auto bad = [&](const char* field, const std::string& why) { throw Error(what + ": field '" + field + "': " + why); };
    if (!o.grid || !o.grid->valid()) bad("grid", "has no valid distance grid");
    if (!is_finite(o.pose.position)) bad("pose", "position must be finite");
    const Quat& q = o.pose.orientation;
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (!(std::abs(n - 1.0) <= 1e-6)) bad("pose", "orientation must be a unit quaternion, |q| = " + format_number(n));
    if (!(std::isfinite(o.stiffness_n_per_m) && o.stiffness_n_per_m > 0.0 && o.stiffness_n_per_m <= 1e5))
        bad("stiffness_n_per_m", "must be in (0, 100000] N/m, got " + format_number(o.stiffness_n_per_m));
}

ElasticContacts reference_contacts(const ReferenceObject& object, const ToolPoints& points, const Pose& tool_world) {
    ElasticContacts out;
    if (!object.grid || !is_finite(tool_world.position) || !std::isfinite(tool_world.orientation.w) ||
        !std::isfinite(tool_world.orientation.x) || !std::isfinite(tool_world.orientation.y) ||
        !std::isfinite(tool_world.orientation.z))
        return out;
    const Quat to_local = glm::conjugate(object.pose.orientation);
    const int n = std::clamp(points.count, 0, kMaxToolPoints);
    for (int i = 0; i < n; ++i) {
        const Vec3 p = tool_point_world(tool_world, points.local_m[i]);
        const Vec3 local = to_local * (p - object.pose.position);
        double d = 0.0;
        Vec3 grad(0.0);
        if (!object.grid->sample(local, d, grad)) continue;
        const double depth = points.radius_m - d;
        const double len = glm::length(grad);
        if (!(depth > 0.0) || !(len > 0.0) || !std::isfinite(len)) continue;
        ElasticContact& c = out.contact[out.count++];
        c.normal = object.pose.orientation * (grad / len);
        c.surface_m = p - d * c.normal;
        c.depth_m = depth;
    }
    return out;
}

}  // namespace tridex::haptics
