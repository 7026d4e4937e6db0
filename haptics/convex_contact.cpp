// haptics/convex_contact.cpp - a ball against a convex edge or corner: the faces around it, the nearest point of
// their intersection, and the grown solid's tangent plane there.
#include "haptics/convex_contact.hpp"

#include <cmath>

#include "haptics/local_surface.hpp"
#include "haptics/snapshot_depth.hpp"

namespace tridex::haptics::contact {

namespace {

constexpr int kMaxFaces = 8;
// Two triangles' planes are one face when their normals agree this closely and their offsets within this many cells.
constexpr double kSameNormal = 0.9999;
constexpr double kSameOffsetCells = 0.05;
// A fitted face's normal must lie within about 5 degrees of its triangle's.
constexpr double kFitAgreesWithTriangle = 0.996;
// A triangle whose normal lies within about a degree of its rays is square to them.
constexpr double kSquareToRays = 0.9998;
// A face's triangle may stand this far (window spacings) outside another face's half-space and still count as
// convex with it: the two faces' triangles end up to a spacing short of their common edge.
constexpr double kConvexToleranceCells = 0.5;
// A candidate point counts as in a half-space within this distance (m) of its plane.
constexpr double kFeasibleM = 1e-9;

// The faces are looked for under the points at these multiples of the radius along each direction: the ball's own
// points, and a halo beyond them that meets a feature lying between two directions (up to about 48 degrees from the
// nearest) before the ball does, so its faces are known from the first tick of contact.
constexpr double kReach[2] = {1.0, 1.5};

struct Face {
    Vec3 n;      // outward unit normal
    double c;    // offset: the half-space is dot(n, x) <= c
    Triangle t;  // the triangle it came from
    int axis;    // its ray set
};

// True when a face with this plane (outward unit n, offset c) is already listed.
bool listed(const Face* faces, int count, const Vec3& n, double c, double same_offset_m) {
    for (int i = 0; i < count; ++i)
        if (glm::dot(faces[i].n, n) > kSameNormal && std::abs(faces[i].c - c) < same_offset_m) return true;
    return false;
}

// Adds the face of triangle t (set `axis`) unless its plane is listed: the tangent plane of the local surface
// fitted to the rays around it (local_surface.hpp), which is the face's own plane where the triangle spans an edge
// (the fit takes the ends of the sheet that continues it). A triangle no surface fits (too few rays of one sheet,
// too steep to its rays) is no face. False when there is no room left.
bool add_face(const ActiveSurface& s, const Triangle& t, int axis, const Vec3& hip, double same_offset_m, Face* faces,
              int& count) {
    if (listed(faces, count, t.n, glm::dot(t.n, t.on), same_offset_m)) return true;
    const bool exits = (t.exit[0] ? 1 : 0) + (t.exit[1] ? 1 : 0) + (t.exit[2] ? 1 : 0) >= 2;
    const Vec3 centre = (t.q[0] + t.q[1] + t.q[2]) / 3.0;
    SurfacePoint sp;
    // A foot point beyond the fitted patch still gives the patch's plane (sp.normal set): on a flat face, the face.
    if (!nearest_on_local_surface(s, axis, hip, centre, t.q[0], t.n, exits, sp) && sp.normal == Vec3(0.0)) {
        // Too few rays of one sheet to fit (a patch by a corner): a triangle square to its rays, its three ends of one
        // kind at one depth, is a face's own (a triangle spanning an edge has ends on two faces at two depths).
        const bool same_kind = t.exit[0] == t.exit[1] && t.exit[1] == t.exit[2];
        if (!(same_kind && std::abs(t.n[axis]) > kSquareToRays)) return true;
        sp.normal = t.n;
        sp.point_m = t.on;
    }
    // A fit that turns away from its own triangle bent round an edge in its patch: not one face.
    if (glm::dot(sp.normal, t.n) < kFitAgreesWithTriangle) return true;
    const double c = glm::dot(sp.normal, sp.point_m);
    if (listed(faces, count, sp.normal, c, same_offset_m)) return true;
    if (count == kMaxFaces) return false;
    Triangle face = t;
    face.n = sp.normal;
    face.on = sp.point_m;
    faces[count++] = Face{sp.normal, c, face, axis};
    return true;
}

bool feasible(const Face* faces, int count, const Vec3& x) {
    for (int i = 0; i < count; ++i)
        if (glm::dot(faces[i].n, x) - faces[i].c > kFeasibleM) return false;
    return true;
}

// The projection of p on the intersection of the planes of the faces listed in `act` (1..3 of them); false when
// they are dependent (parallel faces, or three through one line).
bool project(const Face* faces, const int* act, int m, const Vec3& p, Vec3& x) {
    if (m == 1) {
        const Face& f = faces[act[0]];
        x = p - (glm::dot(f.n, p) - f.c) * f.n;
        return true;
    }
    if (m == 2) {
        // x = p - l1 n1 - l2 n2 with n_i . x = c_i: a 2x2 Gram system.
        const Face &a = faces[act[0]], &b = faces[act[1]];
        const double g = glm::dot(a.n, b.n);
        const double det = 1.0 - g * g;
        if (!(det > 1e-9)) return false;
        const double ra = glm::dot(a.n, p) - a.c, rb = glm::dot(b.n, p) - b.c;
        const double la = (ra - g * rb) / det, lb = (rb - g * ra) / det;
        x = p - la * a.n - lb * b.n;
        return true;
    }
    // Three faces meet in a point: n_i . x = c_i.
    const glm::dmat3 rows = glm::transpose(glm::dmat3(faces[act[0]].n, faces[act[1]].n, faces[act[2]].n));
    if (!(std::abs(glm::determinant(rows)) > 1e-9)) return false;
    x = glm::inverse(rows) * Vec3(faces[act[0]].c, faces[act[1]].c, faces[act[2]].c);
    return true;
}

// The point of the faces' intersection nearest p and the face nearest it (index): the nearest feasible projection
// on the faces, their pairwise lines and triple points. The nearest point of a polyhedron is the projection on the
// affine hull of the face, edge or corner it lies on, and every feasible candidate is at least as far.
bool nearest_in_intersection(const Face* faces, int count, const Vec3& p, Vec3& best, int& nearest) {
    double best_d2 = -1.0;
    const auto consider = [&](const int* act, int m) {
        Vec3 x;
        if (!project(faces, act, m, p, x) || !feasible(faces, count, x)) return;
        const double d2 = glm::dot(x - p, x - p);
        if (best_d2 < 0.0 || d2 < best_d2) {
            best_d2 = d2;
            best = x;
            nearest = act[0];
        }
    };
    for (int i = 0; i < count; ++i) {
        const int a1[1] = {i};
        consider(a1, 1);
        for (int j = i + 1; j < count; ++j) {
            const int a2[2] = {i, j};
            consider(a2, 2);
            for (int k = j + 1; k < count; ++k) {
                const int a3[3] = {i, j, k};
                consider(a3, 3);
            }
        }
    }
    return best_d2 >= 0.0;
}

// True when every pair of faces is convex: each face's triangle lies inside the other's half-space (within the
// tolerance). A concave pair's triangles lie outside each other's half-spaces.
bool convex(const Face* faces, int count, double tolerance_m) {
    for (int i = 0; i < count; ++i)
        for (int j = 0; j < count; ++j) {
            if (i == j) continue;
            for (const Vec3& q : faces[i].t.q)
                if (glm::dot(faces[j].n, q) - faces[j].c > tolerance_m) return false;
        }
    return true;
}

}  // namespace

const std::array<Vec3, 26>& ball_directions() {
    static const std::array<Vec3, 26> directions = [] {
        std::array<Vec3, 26> u{};
        int k = 0;
        for (int x = -1; x <= 1; ++x)
            for (int y = -1; y <= 1; ++y)
                for (int z = -1; z <= 1; ++z)
                    if (x != 0 || y != 0 || z != 0) u[k++] = glm::normalize(Vec3(x, y, z));
        return u;
    }();
    return directions;
}

bool convex_feature_plane(const ActiveSurface& surface, const Vec3& hip, const Vec3& proxy, double radius,
                          int min_faces, PlaneSearch& out) {
    if (!(radius > 0.0)) return false;
    Face faces[kMaxFaces];
    int count = 0;
    const double spacing = spacing_m(surface);
    for (const double reach : kReach)
        for (const Vec3& u : ball_directions()) {
            const Vec3 p = hip + reach * radius * u;
            if (!touches_material(surface, p)) continue;
            for (int a = 0; a < 3; ++a) {
                Triangle t;
                if (!active_triangle(surface, a, p, hip, 0.0, t)) continue;
                if (!add_face(surface, t, a, hip, kSameOffsetCells * surface.cell_m, faces, count)) return false;
            }
        }
    if (count == 0 || count < min_faces || !convex(faces, count, kConvexToleranceCells * spacing)) return false;
    if (feasible(faces, count, hip)) return false;  // the centre is in material: the plane search's case
    Vec3 x;
    int nearest = 0;
    if (!nearest_in_intersection(faces, count, hip, x, nearest)) return false;
    const double dist = glm::length(hip - x);
    if (!(dist > 0.0 && dist < radius)) return false;
    // The god-object's constraint test: a proxy that already overlapped the feature went through it.
    Vec3 xp;
    int unused = 0;
    const double proxy_dist = feasible(faces, count, proxy) ? 0.0
                              : nearest_in_intersection(faces, count, proxy, xp, unused) ? glm::length(proxy - xp)
                                                                                          : radius;
    if (radius - proxy_dist > kCrossingToleranceCells * spacing) return false;
    out = PlaneSearch{};
    out.tri = faces[nearest].t;
    out.tri.n = (hip - x) / dist;
    out.tri.on = x;
    out.depth = radius - dist;
    out.axis = faces[nearest].axis;
    out.found = true;
    out.feature = true;
    return true;
}

}  // namespace tridex::haptics::contact
