// Accuracy of dual contouring where ball cuts meet each other or a box edge: models with exact chords (box
// minus balls), vertex distance to the exact solid in cells.
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

/// Signed distance to the box minus the balls (grid units): CSG max of the box's and the balls' negated
/// distances (exact away from where the pieces meet, a lower bound of |distance| there).
double carved_sdf(const Vec3& lo, const Vec3& hi, const std::vector<CutBall>& balls, const Vec3& p) {
    const Vec3 q = glm::max(lo - p, p - hi);
    const double box = std::min(std::max(q.x, std::max(q.y, q.z)), 0.0) + glm::length(glm::max(q, Vec3(0.0)));
    double d = box;
    for (const CutBall& ball : balls) d = std::max(d, ball.r - glm::length(p - ball.c));
    return d;
}

/// Largest |sdf| (cells) of the contour's vertices within `near` cells of point `at`; `split_faces`, when given,
/// receives the number of faces the contour split (sub-cell tunnels).
double max_vertex_error(const Vec3& lo, const Vec3& hi, const std::vector<CutBall>& balls, const Vec3& at, double near,
                        std::size_t* split_faces = nullptr) {
    TriDexel model = empty_model(cube_lattice(48));
    fill_rays(model, [&](int a, int u, int v) { return box_minus_balls_chord(lo, hi, balls, a, u, v); });
    Contourer contourer(model);
    contourer.update(model);
    if (split_faces) *split_faces = contourer.stats().split_faces;
    const TriMesh m = contourer.mesh();
    double worst = 0.0;
    for (const Vec3& w : m.positions) {
        const Vec3 g = model.lattice.to_grid(w);
        if (glm::length(g - at) > near) continue;
        worst = std::max(worst, std::abs(carved_sdf(lo, hi, balls, g)));
    }
    return worst;
}

TEST(ContourCuts, ThinFinBetweenTwoBallCutsStaysWithinTheBound) {
    // Two balls of radius 6 cells, centres 11 cells apart, one cell above the top face z = 40 of a box: the
    // material left between them is a fin whose sharp ridge (where the spheres meet) lies 1.4 cells under
    // the top face, with a 48 degree tip. Lattice phases: the fin moved by fractions of a cell.
    double worst = 0.0;
    for (int i = 0; i < 8; ++i) {
        const double s = 0.137 * i, t = 0.091 * i;
        const std::vector<CutBall> balls{{Vec3(18.0 + s, 24.0 + t, 41.0), 6.0}, {Vec3(29.0 + s, 24.0 + t, 41.0), 6.0}};
        worst = std::max(worst, max_vertex_error(Vec3(8.0), Vec3(40.0), balls, Vec3(23.5 + s, 24.0 + t, 38.6), 8.0));
    }
    std::printf("thin fin: max vertex error %.3f cells\n", worst);
    EXPECT_LE(worst, 0.45);
}

TEST(ContourCuts, BoxEdgeBesideABallCutKeepsItsVertices) {
    // A box with faces on lattice nodes and a ball bite out of its top edge y = z = 40 (two sizes, eight
    // lattice phases each): crossings next to the bite read a normal across the cut, whose free QEF
    // minimiser leaves the cell; minimised over the cell instead, the vertices stay within a quarter cell.
    double worst = 0.0;
    for (const double r : {3.0, 4.0})
        for (int i = 0; i < 8; ++i) {
            const double s = 0.113 * i;
            const std::vector<CutBall> balls{{Vec3(24.0 + s, 41.0 - 0.3 * s, r == 3.0 ? 41.0 + 0.2 * s : 42.0 + 0.2 * s), r}};
            worst = std::max(worst, max_vertex_error(Vec3(8.0), Vec3(40.0), balls, Vec3(24.0 + s, 40.0, 40.0), 9.0));
        }
    std::printf("box edge beside a cut: max vertex error %.3f cells\n", worst);
    EXPECT_LE(worst, 0.25);
}

TEST(ContourCuts, SheetThinnerThanACellKeepsItsVerticesOnAWall) {
    // Two large balls (radius 60 cells) cut a box from both sides and leave a sheet 0.5 to 0.9 cells thick
    // between their nearly flat, facing walls (tilted against the lattice, eight lattice phases). A cell
    // component holding crossings on both walls has nearly opposite normals: its one vertex cannot lie on
    // both walls, and it lies on one of them instead of between them.
    double worst = 0.0;
    for (const double w : {0.5, 0.7, 0.9})
        for (int i = 0; i < 8; ++i) {
            const double s = 0.137 * i;
            const Vec3 c(24.0 + s, 24.0 + 0.6 * s, 24.0 + 0.3 * s);
            const Vec3 n = glm::normalize(Vec3(1.0, 0.35, 0.2));
            const std::vector<CutBall> balls{{c - (60.0 + 0.5 * w) * n, 60.0}, {c + (60.0 + 0.5 * w) * n, 60.0}};
            worst = std::max(worst, max_vertex_error(Vec3(8.0), Vec3(40.0), balls, c, 4.0));
        }
    std::printf("sheet thinner than a cell: max vertex error %.3f cells\n", worst);
    EXPECT_LE(worst, 0.15);
}

TEST(ContourCuts, SplitFaceInASheetLiesOnAWall) {
    // A sheet 0.6 to 0.95 cells thick between two large balls (radius 60 cells), its walls about 45 degrees to
    // the x and y axes: a z face whose two diagonal corners along the sheet are inside and whose other two lie
    // beyond either wall is ambiguous, and where the cells above and below both keep its inside corners apart the
    // face is split (the tunnel repair). Each split segment joins a crossing on one wall (along x) to one on the
    // other wall (along y); its vertex lies on one wall, not inside the sheet between them (half its thickness).
    double worst = 0.0;
    std::size_t splits = 0;
    for (const double w : {0.6, 0.75, 0.95})
        for (int i = 0; i < 8; ++i) {
            const double s = 0.137 * i;
            const Vec3 c(24.0 + s, 24.0 + 0.6 * s, 24.0 + 0.3 * s);
            const Vec3 n = glm::normalize(Vec3(1.0, 0.8 + 0.05 * i, 0.1));
            const std::vector<CutBall> balls{{c - (60.0 + 0.5 * w) * n, 60.0}, {c + (60.0 + 0.5 * w) * n, 60.0}};
            std::size_t split = 0;
            worst = std::max(worst, max_vertex_error(Vec3(8.0), Vec3(40.0), balls, c, 8.0, &split));
            splits += split;
        }
    std::printf("split faces in a sheet: %zu, max vertex error %.3f cells\n", splits, worst);
    EXPECT_GT(splits, 0u);  // the configuration exercises the tunnel repair
    EXPECT_LE(worst, 0.25);
}

/// Signed distance to the box plus the balls (grid units): CSG min of the pieces' distances (exact outside the
/// solid, a bound of |distance| inside where the pieces meet).
double added_sdf(const Vec3& lo, const Vec3& hi, const std::vector<AddedBall>& balls, const Vec3& p) {
    const Vec3 q = glm::max(lo - p, p - hi);
    double d = std::min(std::max(q.x, std::max(q.y, q.z)), 0.0) + glm::length(glm::max(q, Vec3(0.0)));
    for (const AddedBall& ball : balls) d = std::min(d, glm::length(p - ball.c) - ball.r);
    return d;
}

TEST(ContourCuts, ThirdBallFillingACreaseCornerKeepsTheVertexOnIt) {
    // Three balls added onto a box's top face (top off the nodes): two of them, or one and the top face, meet in a
    // concave crease, and the third fills its corner inside a cell without crossing that cell's edges, so the
    // cell's own tangent planes meet about half a cell inside the third ball. A face-adjacent cell's crossing on the
    // third ball cuts that crease point off, and its plane joins the QEF.
    double worst = 0.0;
    for (const BallsOnABox& k : balls_filling_crease_corners()) {
        const Vec3 lo(6.0), hi(42.0, 42.0, k.top);
        TriDexel model = empty_model(cube_lattice(48));
        fill_rays(model, [&](int a, int u, int v) { return box_plus_balls_chord(lo, hi, k.balls, a, u, v); });
        Contourer contourer(model);
        contourer.update(model);
        const TriMesh m = contourer.mesh();
        expect_closed_manifold(m);
        for (const Vec3& w : m.positions) worst = std::max(worst, std::abs(added_sdf(lo, hi, k.balls, model.lattice.to_grid(w))));
    }
    std::printf("third ball in a crease corner: max vertex error %.3f cells\n", worst);
    EXPECT_LE(worst, 0.3);
}

/// Largest |added_sdf| (cells) of the contour's vertices of the box [lo, hi] plus `balls` on a 48^3 lattice within
/// `near` cells of point `at`; the mesh must be a closed 2-manifold.
double max_added_error(const Vec3& lo, const Vec3& hi, const std::vector<AddedBall>& balls, const Vec3& at, double near) {
    TriDexel model = empty_model(cube_lattice(48));
    fill_rays(model, [&](int a, int u, int v) { return box_plus_balls_chord(lo, hi, balls, a, u, v); });
    Contourer contourer(model);
    contourer.update(model);
    const TriMesh m = contourer.mesh();
    expect_closed_manifold(m);
    double worst = 0.0;
    for (const Vec3& w : m.positions) {
        const Vec3 g = model.lattice.to_grid(w);
        if (glm::length(g - at) <= near) worst = std::max(worst, std::abs(added_sdf(lo, hi, balls, g)));
    }
    return worst;
}

TEST(ContourCuts, AirGapBetweenTwoAddedBallsKeepsItsVertexOnAWall) {
    // Two balls added onto a box's top face with an air gap narrower than a cell between them. Where the gap runs
    // through a cell, each of its crossings reads the other wall on a neighbouring ray and gets no normal, so the
    // vertex was the crossings' mass point, in the gap about half its width from both walls; it now borrows the
    // face-adjacent cells' normals and lies on one wall.
    double worst = 0.0;
    for (const AirGapModel& k : air_gaps_between_added_balls())
        worst = std::max(worst, max_added_error(Vec3(6.0), Vec3(42.0, 42.0, k.model.top), k.model.balls, k.mid, 4.0));
    std::printf("air gap between two added balls: max vertex error %.3f cells\n", worst);
    EXPECT_LE(worst, 0.25);
}

TEST(ContourCuts, FinCrestThinnerThanACellKeepsItsVertexOnAWall) {
    // Two ball cuts leave a fin whose top is thinner than a cell. At its crest a crossing's neighbouring ray on one
    // side reads the fin's other wall and the ray on the far side has no end within reach, so its one-sided normal
    // lies between the walls; the crossings on the other wall have none. The vertex lay inside the fin, up to about
    // half a cell from both walls; the face-adjacent cells' normals contradict the one-sided ones, so the crossings
    // without a normal borrow theirs and the vertex lies on a wall.
    double worst = 0.0;
    for (const FinCrestModel& k : fin_crests_between_ball_cuts())
        worst = std::max(worst, max_vertex_error(Vec3(8.0), Vec3(40.0, 40.0, k.top), k.balls, k.crest, 6.0));
    std::printf("fin crest thinner than a cell: max vertex error %.3f cells\n", worst);
    EXPECT_LE(worst, 0.3);
}

}  // namespace
}  // namespace tridex::compute
