// bench/accuracy/bench_accuracy_exact.hpp - `tridex bench --accuracy`: the stroke programs on a box workpiece and
// their exact answer (signed distance of the exact solid, exact surface samples, reference volume).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "compute/tools/sweep.hpp"
#include "core/aabb.hpp"
#include "core/math.hpp"

namespace tridex::bench::accuracy {

/// Lattice side, m: the lattice is [0, kLatticeSideM]^3 with N cells per side (cell = kLatticeSideM / N).
constexpr double kLatticeSideM = 0.128;
/// The workpiece: a 0.1 m cube [kBoxLoM, kBoxHiM]^3 (faces generally off the lattice nodes).
constexpr double kBoxLoM = 0.014;
constexpr double kBoxHiM = 0.114;

/// One exact tool move: the tool translated in a straight line from a to b (world m). The programs give
/// tridex and OpenVDB the same move split into segments of at most Program::segment_m.
struct Move {
    Vec3 a{0.0};
    Vec3 b{0.0};
};

/// A stroke program: one tool, one operation, a list of exact moves, all in metres (the same at every N).
struct Program {
    std::string name;                         ///< "pocket", "random_ball", "flat_random", "plunge", "union", "paint"
    ToolOp op = ToolOp::kSubtract;            ///< kSubtract, kUnion or kPaint
    compute::SweepTool tool{};                ///< ball or flat-end (flat-end: axis +z, moves horizontal or along z)
    std::uint8_t material = 1;                ///< material the op writes
    double segment_m = 0.001;                 ///< longest segment a move is split into, m
    std::vector<Move> moves;                  ///< exact moves, in order

    /// The moves split into segments of at most segment_m (each move into ceil(len / segment_m) equal
    /// parts, at least one), as tridex sweeps (axis +z).
    std::vector<compute::Sweep> sweeps() const;
};

/// The names of all programs, in bench order.
std::vector<std::string> program_names();

/// Builds program `name` (see program_names()); fixed seeds, so every call gives the same moves.
/// Throws tridex::Error on an unknown name. `short_program` keeps only the first few moves (tests).
Program make_program(const std::string& name, bool short_program = false);

/// The exact solid of a program: the box minus (kSubtract) or plus (kUnion) the union of the exact swept
/// volumes of its moves (kPaint: the box alone). Ball moves are capsules; a flat-end move along +z axis
/// that is horizontal or vertical sweeps an extruded stadium (2D capsule in xy times a z range), whose SDF
/// is exact. Other flat-end moves are rejected (the programs make none).
class ExactSolid {
public:
    /// Throws tridex::Error when a flat-end move is neither horizontal nor vertical.
    explicit ExactSolid(const Program& program);

    /// Signed distance, m (< 0 inside). Exact for points whose nearest surface point lies on one
    /// primitive's face region; CSG max/min of SDFs is a lower bound of |distance| near edges where
    /// primitives meet.
    double sdf(const Vec3& p) const;

    /// Points on the exact surface, roughly area-uniform: `per_m2` samples per square metre of each
    /// primitive's surface, kept when they lie on the composite surface (|sdf| < 1e-7 m). Quasi-random,
    /// fixed seed.
    std::vector<Vec3> surface_samples(double per_m2) const;

    /// Reference volume, m^3: exact box volume minus (plus) the tools' contribution, which is estimated by
    /// `samples` quasi-random (R3 sequence) points in the tools' bounding box; `sigma_m3` receives the
    /// binomial standard error of that estimate (conservative for quasi-random points). kPaint: exact.
    double volume_m3(std::size_t samples, double& sigma_m3) const;

    /// Bounding box of the tools' swept volumes, m.
    Aabb tool_bounds() const;

private:
    double tools_sdf(const Vec3& p) const;
    double box_sdf(const Vec3& p) const;
    double prim_sdf(std::size_t i, const Vec3& p) const;

    struct Prim {
        Vec3 a, b;        // capsule: segment; stadium: xy segment at z = a.z
        double r = 0.0;
        double z0 = 0.0, z1 = 0.0;  // stadium z range
        bool stadium = false;
    };
    ToolOp op_;
    std::vector<Prim> prims_;
};

}  // namespace tridex::bench::accuracy
