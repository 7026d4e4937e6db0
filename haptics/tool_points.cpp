// haptics/tool_points.cpp - tool contact-point sets, their check, axis-angle rotations.
#include "haptics/tool_points.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "haptics/mesh_tool_points.hpp"

namespace tridex::haptics {

namespace {

constexpr double kUnitTolerance = 1e-9;

std::string indexed(const char* field, int i) { return std::string("ToolPoints.") + field + "[" + std::to_string(i) + "]"; }

}  // namespace

ToolPoints ToolPoints::single(double radius_m) {
    if (!(std::isfinite(radius_m) && radius_m >= 0.0))
        throw Error("ToolPoints::single: radius_m = " + std::to_string(radius_m) + " must be finite and >= 0");
    ToolPoints p;
    p.count = 1;
    p.radius_m = radius_m;
    return p;
}

ToolPoints ToolPoints::wand(double half_length_m) {
    if (!(std::isfinite(half_length_m) && half_length_m > 0.0))
        throw Error("ToolPoints::wand: half_length_m = " + std::to_string(half_length_m) + " must be finite and > 0");
    ToolPoints p;
    p.count = 2;
    p.local_m[0] = Vec3(0.0, half_length_m, 0.0);
    p.normal[0] = Vec3(0.0, 1.0, 0.0);
    p.local_m[1] = Vec3(0.0, -half_length_m, 0.0);
    p.normal[1] = Vec3(0.0, -1.0, 0.0);
    return p;
}

ToolPoints ToolPoints::sphere_mesh(double radius_m, int count) {
    if (!(std::isfinite(radius_m) && radius_m > 0.0))
        throw Error("ToolPoints::sphere_mesh: radius_m = " + std::to_string(radius_m) + " must be finite and > 0");
    if (count < 1 || count > kMaxToolPoints)
        throw Error("ToolPoints::sphere_mesh: count = " + std::to_string(count) + " must be in [1, " +
                    std::to_string(kMaxToolPoints) + "]");
    ToolPoints p;
    p.count = count;
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < count; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / count;
        const double ring = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = golden * i;
        const Vec3 n(ring * std::cos(phi), ring * std::sin(phi), z);
        p.normal[i] = n / glm::length(n);
        p.local_m[i] = radius_m * p.normal[i];
    }
    return p;
}

ToolPoints ToolPoints::flat_end(double radius_m, double length_m, int count) {
    if (!(std::isfinite(radius_m) && radius_m > 0.0) || !(std::isfinite(length_m) && length_m > 0.0))
        throw Error("ToolPoints::flat_end: radius_m = " + std::to_string(radius_m) + " and length_m = " +
                    std::to_string(length_m) + " must be finite and > 0");
    if (count < 8 || count > kMaxToolPoints)
        throw Error("ToolPoints::flat_end: count = " + std::to_string(count) + " must be in [8, " +
                    std::to_string(kMaxToolPoints) + "]");
    ToolPoints p;
    const int rest = count - 1;
    const int face = std::max(2, static_cast<int>(std::lround(0.2 * rest)));
    const int edge = std::max(3, static_cast<int>(std::lround(0.35 * rest)));
    const int side = rest - face - edge;
    const Vec3 down(0.0, -1.0, 0.0);
    auto add = [&p](const Vec3& at, const Vec3& n) {
        p.local_m[p.count] = at;
        p.normal[p.count] = n / glm::length(n);
        ++p.count;
    };
    double turn = 0.0;  // each ring turned half a step against the one before
    auto ring = [&](int n, double rr, double y, bool face_normal, bool edge_normal) {
        const double step = 2.0 * std::numbers::pi / n;
        for (int i = 0; i < n; ++i) {
            const double a = turn + step * i;
            const Vec3 radial(std::cos(a), 0.0, std::sin(a));
            add(Vec3(rr * radial.x, y, rr * radial.z), face_normal ? down : edge_normal ? radial + down : radial);
        }
        turn += 0.5 * step;
    };
    add(Vec3(0.0), down);
    ring(face, 0.5 * radius_m, 0.0, true, false);
    ring(edge, radius_m, 0.0, false, true);
    const int side_rings = side > 0 ? std::max(1, static_cast<int>(std::lround(side / 8.0))) : 0;
    for (int j = 0; j < side_rings; ++j) {
        const int n = side / side_rings + (j < side % side_rings ? 1 : 0);
        ring(n, radius_m, length_m * (j + 1) / side_rings, false, false);
    }
    return p;
}

ToolPoints tool_points_for(const ToolShape& tool, int points, const std::string& what, const TriMesh* mesh_m) {
    validate_tool(tool, what);
    switch (tool.kind) {
        case ToolKind::kBall:
            if (points == 1) return ToolPoints::single(tool.radius_m);
            if (points >= 3 && points <= kMaxToolPoints) return ToolPoints::sphere_mesh(tool.radius_m, points);
            throw Error("points: a ball tool takes 1 (its centre) or 3.." + std::to_string(kMaxToolPoints) +
                        " (an interaction mesh over it), got " + std::to_string(points) +
                        (points == 2 ? " (the wand's 2 points need a flat_end tool)" : ""));
        case ToolKind::kFlatEnd: {
            if (points == 2) {
                ToolPoints p;
                p.count = 2;
                p.local_m[0] = Vec3(0.0, tool.length_m, 0.0);
                p.normal[0] = Vec3(0.0, 1.0, 0.0);
                p.local_m[1] = Vec3(0.0);
                p.normal[1] = Vec3(0.0, -1.0, 0.0);
                return p;
            }
            const int n = points == 1 ? 32 : points;
            if (n < 8 || n > kMaxToolPoints)
                throw Error("points: a flat_end tool takes 1 (32 points over it), 2 (the wand's ends) or 8.." +
                            std::to_string(kMaxToolPoints) + ", got " + std::to_string(points));
            return ToolPoints::flat_end(tool.radius_m, tool.length_m, n);
        }
        case ToolKind::kMesh: {
            if (!mesh_m) throw Error(what + ": a mesh tool's contact points come from its mesh, which was not given");
            const int n = points == 1 ? 32 : points;
            if (n < 8 || n > kMaxToolPoints)
                throw Error("points: a mesh tool takes 1 (32 points over its surface) or 8.." +
                            std::to_string(kMaxToolPoints) + ", got " + std::to_string(points));
            return mesh_surface_points(*mesh_m, n);
        }
    }
    throw Error(what + ": unknown tool kind");
}

void validate(const ToolPoints& points, bool require_normals) {
    if (points.count < 1 || points.count > kMaxToolPoints)
        throw Error("ToolPoints.count = " + std::to_string(points.count) + " must be in [1, " +
                    std::to_string(kMaxToolPoints) + "]");
    if (!(std::isfinite(points.radius_m) && points.radius_m >= 0.0))
        throw Error("ToolPoints.radius_m = " + std::to_string(points.radius_m) + " must be finite and >= 0");
    for (int i = 0; i < points.count; ++i) {
        if (!is_finite(points.local_m[i])) throw Error(indexed("local_m", i) + " is not finite");
        const Vec3& n = points.normal[i];
        if (!is_finite(n)) throw Error(indexed("normal", i) + " is not finite");
        const double len = glm::length(n);
        const bool unit = std::abs(len - 1.0) <= kUnitTolerance;
        if (require_normals && !unit)
            throw Error(indexed("normal", i) + " must be a unit vector (the interaction mesh needs normals)");
        if (!unit && len != 0.0) throw Error(indexed("normal", i) + " must be a unit vector or zero");
    }
}

Quat rotation_from_axis_angle(const Vec3& axis, double angle_rad) {
    if (!is_finite(axis)) throw Error("rotation_from_axis_angle: axis is not finite");
    if (!std::isfinite(angle_rad)) throw Error("rotation_from_axis_angle: angle_rad is not finite");
    const double len = glm::length(axis);
    if (!(len > 0.0) || !std::isfinite(len)) throw Error("rotation_from_axis_angle: axis has zero length");
    return glm::angleAxis(angle_rad, axis / len);
}

Vec3 tool_point_world(const Pose& tool, const Vec3& local_m) { return tool.orientation * local_m + tool.position; }

double max_point_distance_m(const ToolPoints& points) {
    double d = 0.0;
    for (int i = 0; i < points.count && i < kMaxToolPoints; ++i) d = std::max(d, glm::length(points.local_m[i]));
    return d;
}

}  // namespace tridex::haptics
