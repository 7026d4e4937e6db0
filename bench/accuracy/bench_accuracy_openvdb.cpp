// bench/accuracy/bench_accuracy_openvdb.cpp - the OpenVDB level-set peer (compiled with TRIDEX_HAVE_OPENVDB).
#include "bench/accuracy/bench_accuracy_openvdb.hpp"

#include "core/error.hpp"

#ifdef TRIDEX_HAVE_OPENVDB
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetMeasure.h>
#include <openvdb/tools/LevelSetSphere.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/global_control.h>

#include <chrono>
#include <cmath>
#endif

namespace tridex::bench::accuracy {

#ifndef TRIDEX_HAVE_OPENVDB

bool openvdb_available() { return false; }
std::string openvdb_version() { return ""; }
PeerRun run_openvdb(const Program&, double, double, const Vec3&) { throw Error("bench --accuracy: built without OpenVDB"); }

#else

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kArcPoints = 64;  // per half circle of the flat-end tool's swept stadium

openvdb::Vec3f vf(const Vec3& p) { return openvdb::Vec3f(float(p.x), float(p.y), float(p.z)); }

/// The swept solid of a flat-end (axis +z) segment: stadium around xy segment a -> b, z in [z0, z1].
openvdb::FloatGrid::Ptr stadium_level_set(const Vec3& a, const Vec3& b, double r, double z0, double z1,
                                          const openvdb::math::Transform& xform, float half_width) {
    std::vector<openvdb::Vec3s> pts;
    std::vector<openvdb::Vec3I> tris;
    const double dx = b.x - a.x, dy = b.y - a.y;
    const bool point = std::hypot(dx, dy) < 1e-12;
    const double th = point ? 0.0 : std::atan2(dy, dx);
    std::vector<std::array<double, 2>> ring;  // CCW
    const int last = point ? kArcPoints - 1 : kArcPoints;
    for (int i = 0; i <= last; ++i) {
        const double ang = th - 0.5 * kPi + kPi * i / kArcPoints;
        ring.push_back({b.x + r * std::cos(ang), b.y + r * std::sin(ang)});
    }
    for (int i = 0; i <= last; ++i) {
        const double ang = th + 0.5 * kPi + kPi * i / kArcPoints;
        ring.push_back({a.x + r * std::cos(ang), a.y + r * std::sin(ang)});
    }
    const auto m = static_cast<unsigned>(ring.size());
    for (const auto& q : ring) pts.emplace_back(float(q[0]), float(q[1]), float(z0));
    for (const auto& q : ring) pts.emplace_back(float(q[0]), float(q[1]), float(z1));
    pts.emplace_back(float(0.5 * (a.x + b.x)), float(0.5 * (a.y + b.y)), float(z0));
    pts.emplace_back(float(0.5 * (a.x + b.x)), float(0.5 * (a.y + b.y)), float(z1));
    const unsigned cb = 2 * m, ct = 2 * m + 1;
    for (unsigned i = 0; i < m; ++i) {
        const unsigned j = (i + 1) % m;
        tris.emplace_back(cb, j, i);          // bottom, facing -z
        tris.emplace_back(ct, m + i, m + j);  // top, facing +z
        tris.emplace_back(i, j, m + j);       // side
        tris.emplace_back(i, m + j, m + i);
    }
    return openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(xform, pts, tris, half_width);
}

}  // namespace

bool openvdb_available() { return true; }
std::string openvdb_version() { return openvdb::getLibraryAbiVersionString(); }

PeerRun run_openvdb(const Program& program, double voxel_m, double half_width, const Vec3& origin_m) {
    using Clock = std::chrono::steady_clock;
    openvdb::initialize();
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    const auto xform = openvdb::math::Transform::createLinearTransform(voxel_m);
    const float hw = static_cast<float>(half_width);
    PeerRun run;
    auto grid = openvdb::tools::createLevelSetBox<openvdb::FloatGrid>(
        openvdb::BBoxd(openvdb::Vec3d(kBoxLoM - origin_m.x, kBoxLoM - origin_m.y, kBoxLoM - origin_m.z),
                       openvdb::Vec3d(kBoxHiM - origin_m.x, kBoxHiM - origin_m.y, kBoxHiM - origin_m.z)), *xform, hw);
    const std::vector<compute::Sweep> sweeps = program.sweeps();
    run.segments = sweeps.size();
    const bool ball = program.tool.kind == compute::ToolKind::kBall;
    const double r = program.tool.radius_m, L = program.tool.length_m;
    auto combine = [&](openvdb::FloatGrid::Ptr tool) {
        if (program.op == ToolOp::kUnion) openvdb::tools::csgUnion(*grid, *tool);
        else openvdb::tools::csgDifference(*grid, *tool);
    };
    const auto t0 = Clock::now();
    if (program.op != ToolOp::kPaint) {
        Vec3 prev_end(std::nan(""));
        for (const compute::Sweep& s : sweeps) {
            const Vec3 a = s.path_m.a - origin_m, b = s.path_m.b - origin_m;  // voxel (0,0,0) at the lattice origin
            if (ball) {
                const int k = std::max(1, static_cast<int>(std::ceil(glm::length(b - a) / (0.5 * voxel_m))));
                for (int i = (a == prev_end) ? 1 : 0; i <= k; ++i)
                    combine(openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
                        float(r), vf(a + (b - a) * (double(i) / k)), float(voxel_m), hw));
            } else {
                const double z0 = std::min(a.z, b.z), z1 = std::max(a.z, b.z) + L;
                combine(stadium_level_set(a, b, r, z0, z1, *xform, hw));
            }
            prev_end = b;
        }
    }
    run.sculpt_s = program.op == ToolOp::kPaint ? 0.0 : std::chrono::duration<double>(Clock::now() - t0).count();
    run.memory_bytes = static_cast<std::size_t>(grid->memUsage());
    run.volume_m3 = openvdb::tools::levelSetVolume(*grid);
    const auto t1 = Clock::now();
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> tris;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*grid, points, tris, quads, 0.0);
    run.mesh_s = std::chrono::duration<double>(Clock::now() - t1).count();
    for (const auto& p : points) run.mesh.positions.push_back(Vec3(p.x(), p.y(), p.z()) + origin_m);
    for (const auto& t : tris) run.mesh.triangles.push_back({t.x(), t.y(), t.z()});
    for (const auto& q : quads) {
        run.mesh.triangles.push_back({q[0], q[1], q[2]});
        run.mesh.triangles.push_back({q[0], q[2], q[3]});
    }
    return run;
}

#endif

}  // namespace tridex::bench::accuracy
