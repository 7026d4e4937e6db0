// bench/accuracy/bench_accuracy_exact.cpp - stroke programs and the exact solid they make.
#include "bench/accuracy/bench_accuracy_exact.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include "core/error.hpp"

namespace tridex::bench::accuracy {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A 64-bit LCG with a fixed seed: uniform doubles in [0, 1).
struct Lcg {
    std::uint64_t state;
    double operator()() {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
    }
};

/// Roberts' R_d quasi-random sequence in [0, 1)^4 (low discrepancy, no seed).
struct R4 {
    double alpha[4];
    std::uint64_t n = 0;
    R4() {
        double g = 1.5;  // root of x^5 = x + 1
        for (int i = 0; i < 60; ++i) g -= (std::pow(g, 5) - g - 1.0) / (5.0 * std::pow(g, 4) - 1.0);
        for (int i = 0; i < 4; ++i) alpha[i] = 1.0 / std::pow(g, i + 1);
    }
    void next(double out[4]) {
        ++n;
        for (int i = 0; i < 4; ++i) {
            const double v = 0.5 + alpha[i] * static_cast<double>(n);
            out[i] = v - std::floor(v);
        }
    }
};

double capsule_sdf(const Vec3& p, const Vec3& a, const Vec3& b, double r) {
    const Vec3 ab = b - a, ap = p - a;
    const double l2 = glm::dot(ab, ab);
    const double t = l2 > 0.0 ? std::clamp(glm::dot(ap, ab) / l2, 0.0, 1.0) : 0.0;
    return glm::length(ap - t * ab) - r;
}

/// Orthonormal e1, e2 perpendicular to unit d.
void basis(const Vec3& d, Vec3& e1, Vec3& e2) {
    e1 = glm::normalize(std::abs(d.x) < 0.9 ? glm::cross(d, Vec3(1, 0, 0)) : glm::cross(d, Vec3(0, 1, 0)));
    e2 = glm::cross(d, e1);
}

void add_polyline(Program& p, const std::vector<Vec3>& pts) {
    for (std::size_t i = 1; i < pts.size(); ++i) p.moves.push_back({pts[i - 1], pts[i]});
}

}  // namespace

std::vector<compute::Sweep> Program::sweeps() const {
    std::vector<compute::Sweep> out;
    compute::Sweep s;
    s.op = op;
    s.tool = tool;
    s.material = material;
    s.axis = Vec3(0, 0, 1);
    for (const Move& m : moves) {
        const int parts = std::max(1, static_cast<int>(std::ceil(glm::length(m.b - m.a) / segment_m - 1e-9)));
        for (int i = 0; i < parts; ++i) {
            s.path_m = Segment{m.a + (m.b - m.a) * (double(i) / parts), m.a + (m.b - m.a) * (double(i + 1) / parts)};
            out.push_back(s);
        }
    }
    return out;
}

std::vector<std::string> program_names() { return {"pocket", "random_ball", "flat_random", "plunge", "union", "paint"}; }

Program make_program(const std::string& name, bool short_program) {
    Program p;
    p.name = name;
    const double top = kBoxHiM;
    Lcg rng{0x9E3779B97F4A7C15ull ^ std::hash<std::string>{}(name)};
    auto in = [&rng](double lo, double hi) { return lo + (hi - lo) * rng(); };
    if (name == "pocket" || name == "paint") {
        // Ball raster: passes along x, 5 mm stepover along y, serpentine.
        p.op = name == "pocket" ? ToolOp::kSubtract : ToolOp::kPaint;
        p.material = name == "pocket" ? 1 : 3;
        p.tool = {compute::ToolKind::kBall, 0.006, 0.0};
        const double z = name == "pocket" ? top + 0.006 - 0.004 : top + 0.002;  // 4 mm deep / 2 mm above
        std::vector<Vec3> pts;
        for (int k = 0; k <= 12; ++k) {
            const double y = 0.034 + 0.005 * k;
            const bool fwd = k % 2 == 0;
            pts.push_back({fwd ? 0.034 : 0.094, y, z});
            pts.push_back({fwd ? 0.094 : 0.034, y, z});
        }
        add_polyline(p, pts);
    } else if (name == "random_ball" || name == "union") {
        const bool uni = name == "union";
        p.op = uni ? ToolOp::kUnion : ToolOp::kSubtract;
        p.material = uni ? 2 : 1;
        const double r = uni ? 0.005 : 0.006;
        p.tool = {compute::ToolKind::kBall, r, 0.0};
        const double lo = uni ? 0.02 : 0.012, hi = kLatticeSideM - lo;  // random_ball also cuts the box's edges
        std::vector<Vec3> pts;
        for (int i = 0; i < (uni ? 13 : 25); ++i)
            pts.push_back({in(lo, hi), in(lo, hi), uni ? top + 0.001 : in(top - 0.002, top + 0.004)});
        add_polyline(p, pts);
    } else if (name == "flat_random") {
        // Flat-end mill, axis +z: horizontal moves at random depths joined by vertical moves.
        p.tool = {compute::ToolKind::kFlatEnd, 0.005, 0.03};
        std::vector<Vec3> pts;
        Vec3 q{in(0.02, 0.108), in(0.02, 0.108), top - in(0.001, 0.006)};
        pts.push_back(q);
        for (int i = 0; i < 12; ++i) {
            q = Vec3(in(0.02, 0.108), in(0.02, 0.108), q.z);
            pts.push_back(q);
            q.z = top - in(0.001, 0.006);
            pts.push_back(q);
        }
        add_polyline(p, pts);
    } else if (name == "plunge") {
        p.tool = {compute::ToolKind::kFlatEnd, 0.005, 0.03};
        for (int k = 0; k < 9; ++k) {
            const double x = 0.034 + 0.03 * (k % 3), y = 0.034 + 0.03 * (k / 3);
            p.moves.push_back({Vec3(x + 0.0003 * k, y, top + 0.002), Vec3(x + 0.0003 * k, y, top - 0.006 - 0.001 * k)});
        }
    } else {
        throw Error("bench --accuracy: unknown program '" + name + "'");
    }
    if (short_program && p.moves.size() > 3) p.moves.resize(3);
    return p;
}

ExactSolid::ExactSolid(const Program& program) : op_(program.op) {
    if (op_ == ToolOp::kPaint) return;
    for (const Move& m : program.moves) {
        Prim pr;
        pr.r = program.tool.radius_m;
        if (program.tool.kind == compute::ToolKind::kBall) {
            pr.a = m.a;
            pr.b = m.b;
        } else {
            pr.stadium = true;
            const double L = program.tool.length_m;
            if (std::abs(m.a.z - m.b.z) < 1e-12) {
                pr.a = m.a;
                pr.b = m.b;
                pr.z0 = m.a.z;
                pr.z1 = m.a.z + L;
            } else if (std::abs(m.a.x - m.b.x) < 1e-12 && std::abs(m.a.y - m.b.y) < 1e-12) {
                pr.a = pr.b = m.a;
                pr.z0 = std::min(m.a.z, m.b.z);
                pr.z1 = std::max(m.a.z, m.b.z) + L;
            } else {
                throw Error("bench --accuracy: flat-end moves must be horizontal or along the axis");
            }
        }
        prims_.push_back(pr);
    }
}

double ExactSolid::prim_sdf(std::size_t i, const Vec3& p) const {
    const Prim& q = prims_[i];
    if (!q.stadium) return capsule_sdf(p, q.a, q.b, q.r);
    const double d2 = capsule_sdf(Vec3(p.x, p.y, 0.0), Vec3(q.a.x, q.a.y, 0.0), Vec3(q.b.x, q.b.y, 0.0), q.r);
    const double dz = std::max(q.z0 - p.z, p.z - q.z1);
    return std::min(std::max(d2, dz), 0.0) + std::hypot(std::max(d2, 0.0), std::max(dz, 0.0));
}

double ExactSolid::tools_sdf(const Vec3& p) const {
    double d = 1e9;
    for (std::size_t i = 0; i < prims_.size(); ++i) d = std::min(d, prim_sdf(i, p));
    return d;
}

double ExactSolid::box_sdf(const Vec3& p) const {
    const Vec3 c(0.5 * (kBoxLoM + kBoxHiM)), h(0.5 * (kBoxHiM - kBoxLoM));
    const Vec3 q = glm::abs(p - c) - h;
    return glm::length(glm::max(q, Vec3(0.0))) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
}

double ExactSolid::sdf(const Vec3& p) const {
    const double b = box_sdf(p);
    if (op_ == ToolOp::kPaint || prims_.empty()) return b;
    const double t = tools_sdf(p);
    return op_ == ToolOp::kUnion ? std::min(b, t) : std::max(b, -t);
}

Aabb ExactSolid::tool_bounds() const {
    Aabb box;
    for (const Prim& q : prims_) {
        Aabb pb;
        pb.add(q.a);
        pb.add(q.b);
        pb = pb.inflated(q.r);
        if (q.stadium) {
            pb.lo.z = q.z0;
            pb.hi.z = q.z1;
        }
        box.add(pb.lo);
        box.add(pb.hi);
    }
    return box;
}

std::vector<Vec3> ExactSolid::surface_samples(double per_m2) const {
    std::vector<Vec3> out;
    R4 seq;
    double u[4];
    auto keep = [&](const Vec3& p) {
        if (std::abs(sdf(p)) < 1e-7) out.push_back(p);
    };
    const double side = kBoxHiM - kBoxLoM;
    for (int face = 0; face < 6; ++face) {
        const int axis = face / 2;
        const auto count = static_cast<std::size_t>(side * side * per_m2);
        for (std::size_t i = 0; i < count; ++i) {
            seq.next(u);
            Vec3 p;
            p[axis] = face % 2 ? kBoxHiM : kBoxLoM;
            p[(axis + 1) % 3] = kBoxLoM + side * u[0];
            p[(axis + 2) % 3] = kBoxLoM + side * u[1];
            keep(p);
        }
    }
    for (const Prim& q : prims_) {
        if (!q.stadium) {
            const double len = glm::length(q.b - q.a);
            const Vec3 d = len > 0.0 ? (q.b - q.a) / len : Vec3(0, 0, 1);
            Vec3 e1, e2;
            basis(d, e1, e2);
            const double a_cyl = 2.0 * kPi * q.r * len, a_sph = 4.0 * kPi * q.r * q.r;
            const auto count = static_cast<std::size_t>((a_cyl + a_sph) * per_m2);
            for (std::size_t i = 0; i < count; ++i) {
                seq.next(u);
                const double phi = 2.0 * kPi * u[2];
                if (u[0] * (a_cyl + a_sph) < a_cyl) {
                    keep(q.a + u[1] * len * d + q.r * (std::cos(phi) * e1 + std::sin(phi) * e2));
                } else {  // a whole sphere at a or b; its half inside the cylinder is rejected by keep()
                    const double z = 1.0 - 2.0 * u[1], s = std::sqrt(std::max(0.0, 1.0 - z * z));
                    keep((u[3] < 0.5 ? q.a : q.b) + q.r * Vec3(s * std::cos(phi), s * std::sin(phi), z));
                }
            }
        } else {
            const Vec3 a(q.a.x, q.a.y, 0.0), b(q.b.x, q.b.y, 0.0);
            const double len = glm::length(b - a), h = q.z1 - q.z0;
            const Vec3 d = len > 0.0 ? (b - a) / len : Vec3(1, 0, 0), n(-d.y, d.x, 0.0);
            const double perim = 2.0 * len + 2.0 * kPi * q.r, a_side = perim * h, a_cap = 2.0 * len * q.r + kPi * q.r * q.r;
            const auto count = static_cast<std::size_t>((a_side + 2.0 * a_cap) * per_m2);
            for (std::size_t i = 0; i < count; ++i) {
                seq.next(u);
                if (u[0] * (a_side + 2.0 * a_cap) < a_side) {
                    const double s = u[1] * perim, z = q.z0 + u[2] * h;
                    Vec3 p;
                    if (s < len) p = a + s * d + q.r * n;
                    else if (s < 2.0 * len) p = a + (s - len) * d - q.r * n;
                    else {
                        const double phi = (s - 2.0 * len) / q.r;  // a whole circle around a or b
                        p = (u[3] < 0.5 ? a : b) + q.r * Vec3(std::cos(phi), std::sin(phi), 0.0);
                    }
                    keep(Vec3(p.x, p.y, z));
                } else {  // a cap: rejection in the stadium's bounding rectangle
                    const Vec3 p = a + (u[1] * (len + 2.0 * q.r) - q.r) * d + (u[2] * 2.0 - 1.0) * q.r * n;
                    if (capsule_sdf(p, a, b, q.r) > 0.0) continue;
                    keep(Vec3(p.x, p.y, u[3] < 0.5 ? q.z0 : q.z1));
                }
            }
        }
    }
    return out;
}

double ExactSolid::volume_m3(std::size_t samples, double& sigma_m3) const {
    const double side = kBoxHiM - kBoxLoM, vbox = side * side * side;
    sigma_m3 = 0.0;
    if (op_ == ToolOp::kPaint || prims_.empty()) return vbox;
    Aabb r = tool_bounds();
    if (op_ == ToolOp::kSubtract) {  // only the part inside the box changes the volume
        r.lo = glm::max(r.lo, Vec3(kBoxLoM));
        r.hi = glm::min(r.hi, Vec3(kBoxHiM));
    }
    const Vec3 size = r.size();
    if (size.x <= 0.0 || size.y <= 0.0 || size.z <= 0.0) return vbox;
    const double vr = size.x * size.y * size.z;
    R4 seq;
    double u[4];
    std::size_t hits = 0;
    for (std::size_t i = 0; i < samples; ++i) {
        seq.next(u);
        const Vec3 p = r.lo + Vec3(u[0], u[1], u[2]) * size;
        if (tools_sdf(p) >= 0.0) continue;
        const bool in_box = box_sdf(p) < 0.0;
        if (op_ == ToolOp::kSubtract ? in_box : !in_box) ++hits;
    }
    const double f = static_cast<double>(hits) / static_cast<double>(samples);
    sigma_m3 = vr * std::sqrt(f * (1.0 - f) / static_cast<double>(samples));
    return op_ == ToolOp::kSubtract ? vbox - f * vr : vbox + f * vr;
}

}  // namespace tridex::bench::accuracy
