// compute/model/workpiece.cpp - fit-to-stock transform and mesh transformation.
#include "compute/model/workpiece.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"

namespace tridex::compute {

Mat4 fit_to_stock(const Aabb& box, const Vec3& centre_m, double stock_size_m) {
    if (!std::isfinite(stock_size_m) || !(stock_size_m > 0.0))
        throw Error("workpiece: stock size must be a positive number of metres, got " + std::to_string(stock_size_m));
    if (!is_finite(centre_m)) throw Error("workpiece: stock centre is not finite");
    const Vec3 size = box.size();
    const double longest = std::max({size.x, size.y, size.z});
    if (box.empty() || !is_finite(box.lo) || !is_finite(box.hi) || !(longest > 0.0))
        throw Error("workpiece: mesh bounding box is empty, flat to a point, or not finite");
    const double s = stock_size_m / longest;
    const Vec3 c = box.centre();
    Mat4 m(s);  // diagonal s, s, s, s
    m[3] = glm::dvec4(centre_m - s * c, 1.0);
    return m;
}

TriMesh transformed(const TriMesh& mesh, const Mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) throw Error("workpiece: transform has a non-finite entry");
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
        throw Error("workpiece: transform is not affine (last row must be 0 0 0 1)");
    const double det = glm::determinant(glm::dmat3(m));
    if (det == 0.0) throw Error("workpiece: transform is singular (determinant 0)");
    TriMesh out;
    out.positions.reserve(mesh.positions.size());
    for (const Vec3& p : mesh.positions) out.positions.push_back(Vec3(m * glm::dvec4(p, 1.0)));
    out.triangles = mesh.triangles;
    if (det < 0.0)
        for (auto& t : out.triangles) std::swap(t[1], t[2]);
    return out;
}

}  // namespace tridex::compute
