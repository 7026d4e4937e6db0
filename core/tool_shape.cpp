// core/tool_shape.cpp - tool shape names, reach and checks.
#include "core/tool_shape.hpp"

#include <cmath>
#include <cstdio>

#include "core/error.hpp"

namespace tridex {

namespace {

std::string num(double v) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

double size_or_zero(double v) { return std::isfinite(v) && v > 0.0 ? v : 0.0; }

}  // namespace

const char* to_string(ToolKind kind) {
    switch (kind) {
        case ToolKind::kBall: return "ball";
        case ToolKind::kFlatEnd: return "flat_end";
        case ToolKind::kMesh: return "mesh";
    }
    return "ball";
}

ToolKind parse_tool_kind(const std::string& name, const std::string& what) {
    for (ToolKind k : {ToolKind::kBall, ToolKind::kFlatEnd, ToolKind::kMesh})
        if (name == to_string(k)) return k;
    throw Error(what + ": unknown tool shape '" + name + "'; use ball, flat_end or mesh");
}

double tool_reach_m(const ToolShape& tool) {
    const double r = size_or_zero(tool.radius_m);
    if (tool.kind != ToolKind::kFlatEnd) return r;
    const double l = size_or_zero(tool.length_m);
    return std::sqrt(r * r + l * l);
}

void validate_tool(const ToolShape& tool, const std::string& what) {
    if (tool.kind != ToolKind::kBall && tool.kind != ToolKind::kFlatEnd && tool.kind != ToolKind::kMesh)
        throw Error(what + ".shape: unknown tool kind " + std::to_string(static_cast<int>(tool.kind)));
    if (!(std::isfinite(tool.radius_m) && tool.radius_m > 0.0))
        throw Error(what + ".radius_m: must be a finite number of metres > 0, got " + num(tool.radius_m));
    if (tool.kind == ToolKind::kFlatEnd && !(std::isfinite(tool.length_m) && tool.length_m > 0.0))
        throw Error(what + ".length_m: a flat_end tool needs a finite length > 0 m, got " + num(tool.length_m));
}

}  // namespace tridex
