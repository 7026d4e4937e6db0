// compute/model/volume.cpp - summing interval lengths of the ray sets, with the trapezoid rule on
// lattice-plane faces.
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

/// Whether the ray of set `e` through lattice node `n` has an interval end exactly at depth n[e].
bool end_on_node(const TriDexel& m, int e, const std::array<int, 3>& n) {
    const RaySet& s = m.sets[e];
    const int u = n[(e + 1) % 3], v = n[(e + 2) % 3];
    if (u < 0 || v < 0 || u >= s.nu || v >= s.nv) return false;
    const auto d = static_cast<float>(n[e]);
    for (const Interval& iv : s.ray(u, v))
        if (iv.enter == d || iv.exit == d) return true;
    return false;
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
    double half_cells = 0.0;  // in units of h^3 / 2
    for (int e = 0; e < 3; ++e) {
        if (e == axis) continue;
        const RaySet& s = model.sets[e];
        for (int v = 0; v < s.nv; ++v)
            for (int u = 0; u < s.nu; ++u)
                for (const Interval& iv : s.ray(u, v))
                    for (const float t : {iv.enter, iv.exit}) {
                        if (!(t == std::floor(t)) || t < 0.0f || t > static_cast<float>(model.lattice.cells[e])) continue;
                        std::array<int, 3> n{};
                        n[e] = static_cast<int>(t);
                        n[(e + 1) % 3] = u;
                        n[(e + 2) % 3] = v;
                        // A face parallel to this set's rays continues to a neighbour node along them; a
                        // surface that this set's ray crosses at the node (a sloped plane through nodes) does not.
                        std::array<int, 3> lo = n, hi = n;
                        --lo[axis];
                        ++hi[axis];
                        if (!end_on_node(model, e, lo) && !end_on_node(model, e, hi)) continue;
                        half_cells += covers(model, axis, n) ? -1.0 : 1.0;
                    }
    }
    const double h = model.lattice.cell_m;
    return 0.5 * half_cells * h * h * h;
}

double dexel_volume_m3(const TriDexel& model) {
    double sum = 0.0;
    for (int a = 0; a < 3; ++a) sum += ray_set_volume_m3(model, a) + lattice_face_correction_m3(model, a);
    return sum / 3.0;
}

}  // namespace tridex::compute
