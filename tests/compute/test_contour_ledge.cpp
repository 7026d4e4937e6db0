// Accuracy of dual contouring on a flat ledge about one ray wide: a box whose top face is cut by a deep strip-shaped
// flat floor next to a shallower flat floor (the step between two flat-end cuts), exact chords, vertex distance to
// the exact solid in cells.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "compute/contour/contour_dual.hpp"
#include "test_contour_models.hpp"

namespace tridex::compute {
namespace {

using namespace testing;

/// The box [8, 40]^3 (grid units) minus a ledge and a shallow pocket: with q = y - y0 - s x (the in-plane
/// coordinate across the strip), the ledge removes z > deep for 0 <= q <= width, the pocket z > deep + step for
/// q > width. Vertical walls, tilted against the lattice by the slope s.
struct Ledge {
    double y0, s, width, deep, step;
};

constexpr double kLo = 8.0, kHi = 40.0;

/// Exact chords of ray (u, v) of set a (grid units).
std::vector<Interval> ledge_chord(const Ledge& l, int a, int u, int v) {
    if (u < kLo || u > kHi || v < kLo || v > kHi) return {};
    std::vector<std::pair<double, double>> spans{{kLo, kHi}};
    const double shallow = l.deep + l.step;
    if (a == 2) {  // z ray at (x, y) = (u, v)
        const double q = v - l.y0 - l.s * u;
        const double top = q < 0.0 ? kHi : q <= l.width ? l.deep : shallow;
        subtract_span(spans, top, kHi + 1.0);
        return spans_to_intervals(spans);
    }
    // x ray at (y, z) = (u, v) or y ray at (z, x) = (u, v): x range or y range of the removed parts at height z.
    const double z = a == 0 ? v : u;
    if (z <= l.deep) return spans_to_intervals(spans);
    if (a == 0) {
        const double y = u;  // q in [0, width] <=> x in [(y - y0 - width) / s, (y - y0) / s]; q > width <=> x < that low end
        const double x_hi = (y - l.y0) / l.s, x_lo = (y - l.y0 - l.width) / l.s;
        subtract_span(spans, z > shallow ? kLo - 1.0 : x_lo, x_hi);
    } else {
        const double x = v;  // q in [0, width] <=> y in [y0 + s x, y0 + s x + width]
        const double y_lo = l.y0 + l.s * x, y_hi = y_lo + l.width;
        subtract_span(spans, y_lo, z > shallow ? kHi + 1.0 : y_hi);
    }
    return spans_to_intervals(spans);
}

/// Signed distance (grid units) to the box minus the ledge and the pocket (CSG max of plane distances: exact on
/// the faces, a lower bound of |distance| where they meet).
double ledge_sdf(const Ledge& l, const Vec3& p) {
    const Vec3 q3 = glm::max(Vec3(kLo) - p, p - Vec3(kHi));
    const double box = std::min(std::max(q3.x, std::max(q3.y, q3.z)), 0.0) + glm::length(glm::max(q3, Vec3(0.0)));
    const double scale = std::sqrt(1.0 + l.s * l.s);
    const double q = (p.y - l.y0 - l.s * p.x) / scale, w = l.width / scale;
    const double ledge = std::max(l.deep - p.z, std::max(-q, q - w));  // the removed ledge as a solid
    const double pocket = std::max(l.deep + l.step - p.z, w - q);
    return std::max(box, std::max(-ledge, -pocket));
}

TEST(ContourLedge, FlatLedgeOneRayWideKeepsItsFloorNormal) {
    // A ledge 1.1 to 1.5 cells wide (across its walls) 2.6 cells under the top face, next to a floor 0.65 cells
    // shallower: a floor crossing on the ledge whose neighbour across the strip on one side is the shallower floor
    // and on the other the top face (beyond the normals' window) reads a one-sided slope to the other floor; the
    // ledge is flat along the strip, so the crossing takes the floor's normal. Lattice phases and tilts.
    double worst = 0.0;
    for (int i = 0; i < 12; ++i) {
        const Ledge l{20.0 + 0.173 * i, 0.25 + 0.03 * i, 1.1 + 0.035 * i, 37.4 - 0.061 * i, 0.65};
        TriDexel model = empty_model(cube_lattice(48));
        fill_rays(model, [&](int a, int u, int v) { return ledge_chord(l, a, u, v); });
        Contourer contourer(model);
        contourer.update(model);
        const TriMesh m = contourer.mesh();
        for (const Vec3& w : m.positions) {
            const Vec3 g = model.lattice.to_grid(w);
            if (g.x < 12.0 || g.x > 36.0 || g.z < 34.0) continue;  // the strip's middle, away from the box's edges
            worst = std::max(worst, std::abs(ledge_sdf(l, g)));
        }
    }
    std::printf("flat ledge one ray wide: max vertex error %.3f cells\n", worst);
    EXPECT_LE(worst, 0.3);
}

}  // namespace
}  // namespace tridex::compute
