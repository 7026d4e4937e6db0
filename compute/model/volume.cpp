// compute/model/volume.cpp - summing interval lengths of the ray sets, with partial columns for
// faces parallel to the rays.
#include "compute/model/volume.hpp"

#include <array>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tridex::compute {
namespace {

void check_axis(int axis, const char* fn) {
    if (axis < 0 || axis > 2) throw Error(std::string(fn) + ": axis must be 0, 1 or 2, got " + std::to_string(axis));
}

/// Whether the ray of set `a` through lattice node `n` covers it (enter <= depth < exit, the half-open
/// rule of contouring); false for a node outside the lattice.
bool covers(const TriDexel& m, int a, const std::array<int, 3>& n) {
    const RaySet& s = m.sets[a];
    const int u = n[(a + 1) % 3], v = n[(a + 2) % 3];
    if (u < 0 || v < 0 || u >= s.nu || v >= s.nv) return false;
    const auto d = static_cast<float>(n[a]);
    for (const Interval& iv : s.ray(u, v))
        if (iv.enter <= d && d < iv.exit) return true;
    return false;
}

/// Whether the ray of set `e` through the lattice line of node `n` has an interval end exactly at depth t.
bool end_at(const TriDexel& m, int e, const std::array<int, 3>& n, float t) {
    const RaySet& s = m.sets[e];
    const int u = n[(e + 1) % 3], v = n[(e + 2) % 3];
    if (u < 0 || v < 0 || u >= s.nu || v >= s.nv) return false;
    const float d = t;
    for (const Interval& iv : s.ray(u, v))
        if (iv.enter == d || iv.exit == d) return true;
    return false;
}

/// Whether e's ray through a neighbour of node n along axis b (either side) ends at exactly depth t.
bool face_continues(const TriDexel& m, int e, const std::array<int, 3>& n, int b, float t) {
    std::array<int, 3> lo = n, hi = n;
    --lo[b];
    ++hi[b];
    return end_at(m, e, lo, t) || end_at(m, e, hi, t);
}

}  // namespace

double ray_set_volume_m3(const TriDexel& model, int axis) {
    check_axis(axis, "ray_set_volume_m3");
    double cells = 0.0;  // grid units: cell-length columns of one cell^2 cross-section
    for (const auto& ray : model.sets[axis].rays)
        for (const Interval& iv : ray) cells += static_cast<double>(iv.exit) - static_cast<double>(iv.enter);
    const double h = model.lattice.cell_m;
    return cells * h * h * h;
}

double lattice_face_correction_m3(const TriDexel& model, int axis) {
    check_axis(axis, "lattice_face_correction_m3");
    double cells = 0.0;  // grid units^3
    for (int e = 0; e < 3; ++e) {
        if (e == axis) continue;
        const RaySet& s = model.sets[e];
        const auto top = static_cast<double>(model.lattice.cells[e]);
        for (int v = 0; v < s.nv; ++v)
            for (int u = 0; u < s.nu; ++u)
                for (const Interval& iv : s.ray(u, v))
                    for (const bool exit : {false, true}) {
                        const float t = exit ? iv.exit : iv.enter;
                        const double m = std::round(static_cast<double>(t));  // the node whose column holds t
                        if (!(m >= 0.0 && m <= top)) continue;
                        std::array<int, 3> n{};
                        n[e] = static_cast<int>(m);
                        n[(e + 1) % 3] = u;
                        n[(e + 2) % 3] = v;
                        // A surface parallel to this set's rays keeps its depth along them. A flat face
                        // perpendicular to e also keeps it along the third axis b, whose rays lie in the
                        // face: e alone sees it (full weight). A sloped or curved wall parallel to the rays
                        // is crossed by e's and b's rays alike: each corrects the column half.
                        if (!face_continues(model, e, n, axis, t)) continue;
                        const double weight = face_continues(model, e, n, 3 - e - axis, t) ? 1.0 : 0.5;
                        // Share of node m's column [m - 1/2, m + 1/2] on the material side of the face.
                        const double inside = exit ? static_cast<double>(t) - m + 0.5 : m + 0.5 - static_cast<double>(t);
                        cells += weight * (inside - (covers(model, axis, n) ? 1.0 : 0.0));
                    }
    }
    const double h = model.lattice.cell_m;
    return cells * h * h * h;
}

double dexel_volume_m3(const TriDexel& model) {
    double sum = 0.0;
    for (int a = 0; a < 3; ++a) sum += ray_set_volume_m3(model, a) + lattice_face_correction_m3(model, a);
    return sum / 3.0;
}

}  // namespace tridex::compute
