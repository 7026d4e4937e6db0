// haptics/local_surface.cpp - quadratic height field fitted to 4 x 4 dexel ends, and its point nearest the HIP.
#include "haptics/local_surface.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "haptics/snapshot_depth.hpp"

namespace tridex::haptics::contact {

namespace {

constexpr int kTerms = 10;           // the quadratic's six terms, then u^3, u^2 v, u v^2, v^3
constexpr int kQuadratic = 6;        // terms of the quadratic, fitted when too few rays qualify for the cubic
constexpr int kMinRaysCubic = 13;    // of the 16 around the point
constexpr int kMinRays = 10;
constexpr double kPlaneBand = 1.0;   // an end counts when within this many spacings of the plane's continuation
constexpr double kResidual = 0.1;    // spacings: a worse fit is an edge or another sheet
constexpr double kMinAlong = 0.3;    // |n . axis| below this: the rays graze the surface
constexpr int kFootSteps = 4;

std::array<double, kTerms> terms(double u, double v) {
    return {1.0, u, v, u * u, u * v, v * v, u * u * u, u * u * v, u * v * v, v * v * v};
}

// Solves the leading nt x nt system m x = b in place (Gaussian elimination, partial pivoting). False when singular.
bool solve(std::array<std::array<double, kTerms>, kTerms>& m, std::array<double, kTerms>& b, int nt) {
    for (int c = 0; c < nt; ++c) {
        int piv = c;
        for (int r = c + 1; r < nt; ++r)
            if (std::abs(m[r][c]) > std::abs(m[piv][c])) piv = r;
        if (!(std::abs(m[piv][c]) > 1e-12)) return false;
        std::swap(m[c], m[piv]);
        std::swap(b[c], b[piv]);
        for (int r = c + 1; r < nt; ++r) {
            const double f = m[r][c] / m[c][c];
            for (int k = c; k < nt; ++k) m[r][k] -= f * m[c][k];
            b[r] -= f * b[c];
        }
    }
    for (int c = nt - 1; c >= 0; --c) {
        for (int k = c + 1; k < nt; ++k) b[c] -= m[c][k] * b[k];
        b[c] /= m[c][c];
    }
    return true;
}

}  // namespace

bool nearest_on_local_surface(const ActiveSurface& s, int a, const Vec3& p, const Vec3& centre, const Vec3& q0,
                              const Vec3& n, bool exits, SurfacePoint& out) {
    const ActiveSurface::Window& w = s.sets[a];
    if (!window_ok(w) || !(std::abs(n[a]) >= kMinAlong)) return false;
    const double sp = s.window_spacing_cells(a) * s.cell_m;  // spacing, m: the fit's unit
    const ActiveSurface::WindowCoord c = s.to_window(a, centre);
    const int iu0 = static_cast<int>(std::floor(c.fu)) - 1, iv0 = static_cast<int>(std::floor(c.fv)) - 1;
    if (!(iu0 >= 0 && iv0 >= 0 && iu0 + 3 <= w.nu - 1 && iv0 + 3 <= w.nv - 1)) return false;
    // Samples in units of the spacing, relative to the centre, in the plane's frame: (u, v) along t1, t2 in the plane,
    // h along n, so that the surface is a gentle height field whatever its tilt to the rays.
    const Vec3 t1 = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, Vec3(1, 0, 0)) : glm::cross(n, Vec3(0, 1, 0)));
    const Vec3 t2 = glm::cross(n, t1);
    std::array<double, 16> su{}, sv{}, sh{};
    int count = 0;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const Vec3 base = s.window_point(a, iu0 + i, iv0 + j, 0.0);
            // The plane's continuation along this ray: base + t * e_a with n . (x - q0) = 0.
            const double t_plane = glm::dot(n, q0 - base) / n[a] / s.cell_m;  // grid units
            const int k = std::min(w.intervals(iu0 + i, iv0 + j), ActiveSurface::kMaxIntervals);
            double best = kPlaneBand * s.window_spacing_cells(a);
            bool found = false;
            double depth = 0.0;
            for (int m = 0; m < k; ++m) {
                const double e = exits ? w.exit(iu0 + i, iv0 + j, m) : w.enter(iu0 + i, iv0 + j, m);
                if (std::abs(e - t_plane) <= best) {
                    best = std::abs(e - t_plane);
                    depth = e;
                    found = true;
                }
            }
            if (!found) continue;
            const Vec3 x = s.window_point(a, iu0 + i, iv0 + j, depth);
            su[count] = glm::dot(x - centre, t1) / sp;
            sv[count] = glm::dot(x - centre, t2) / sp;
            sh[count] = glm::dot(x - centre, n) / sp;
            ++count;
        }
    if (count < kMinRays) return false;
    std::array<std::array<double, kTerms>, kTerms> m{};
    std::array<double, kTerms> b{};
    for (int i = 0; i < count; ++i) {
        const auto f = terms(su[i], sv[i]);
        for (int r = 0; r < kTerms; ++r) {
            for (int k = 0; k < kTerms; ++k) m[r][k] += f[r] * f[k];
            b[r] += f[r] * sh[i];
        }
    }
    const int nt = count >= kMinRaysCubic ? kTerms : kQuadratic;
    if (!solve(m, b, nt)) return false;
    for (int k = nt; k < kTerms; ++k) b[k] = 0.0;
    const auto h = [&](double u, double v) {
        const auto f = terms(u, v);
        double r = 0.0;
        for (int k = 0; k < kTerms; ++k) r += b[k] * f[k];
        return r;
    };
    const auto dhu = [&](double u, double v) {
        return b[1] + 2.0 * b[3] * u + b[4] * v + 3.0 * b[6] * u * u + 2.0 * b[7] * u * v + b[8] * v * v;
    };
    const auto dhv = [&](double u, double v) {
        return b[2] + b[4] * u + 2.0 * b[5] * v + b[7] * u * u + 2.0 * b[8] * u * v + 3.0 * b[9] * v * v;
    };
    for (int i = 0; i < count; ++i)
        if (!(std::abs(h(su[i], sv[i]) - sh[i]) <= kResidual)) return false;
    // The foot point of p: project p onto the tangent plane at the current point, and repeat.
    const Vec3 pl(glm::dot(p - centre, t1) / sp, glm::dot(p - centre, t2) / sp, glm::dot(p - centre, n) / sp);
    double u = pl.x, v = pl.y;
    Vec3 m_local(0.0);
    for (int it = 0; it < kFootSteps; ++it) {
        const double hu = dhu(u, v), hv = dhv(u, v);
        m_local = glm::normalize(Vec3(-hu, -hv, 1.0));
        const Vec3 at(u, v, h(u, v));
        const Vec3 foot = pl - glm::dot(pl - at, m_local) * m_local;
        u = foot.x;
        v = foot.y;
    }
    m_local = glm::normalize(Vec3(-dhu(u, v), -dhv(u, v), 1.0));
    Vec3 normal = glm::normalize(m_local.x * t1 + m_local.y * t2 + m_local.z * n);
    const Vec3 point = centre + sp * (u * t1 + v * t2 + h(u, v) * n);
    if (!is_finite(point) || !is_finite(normal)) return false;
    out.point_m = point;
    out.normal = normal;
    return std::abs(u) <= 1.5 && std::abs(v) <= 1.5;
}

}  // namespace tridex::haptics::contact
