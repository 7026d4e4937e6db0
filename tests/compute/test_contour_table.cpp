// Tests of compute/contour/contour_table: the 256-entry cell component table of manifold dual contouring.
#include <gtest/gtest.h>

#include <bit>

#include "compute/contour/contour_table.hpp"

namespace tridex::compute::contour {
namespace {

int config_of(std::initializer_list<int> inside_corners) {
    int c = 0;
    for (int k : inside_corners) c |= 1 << k;
    return c;
}

TEST(ContourTable, EdgeAndFaceNumbering) {
    // Edge 0 runs along x at y = z = 0: corners 0 -> 1; edge 4+3 along y at z = 1, x = 1: corners 5 -> 7.
    EXPECT_EQ(edge_corners(0), (std::array<int, 2>{0, 1}));
    EXPECT_EQ(edge_corners(4 + 3), (std::array<int, 2>{5, 7}));
    EXPECT_EQ(edge_corners(8 + 1), (std::array<int, 2>{1, 5}));  // along z at x = 1, y = 0
    // Face 4 (z = 0): corners in order of (x, y) offsets.
    EXPECT_EQ(face_corners(4), (std::array<int, 4>{0, 1, 2, 3}));
    EXPECT_EQ(face_corners(1), (std::array<int, 4>{1, 3, 5, 7}));  // x = 1: (y, z) offsets
}

TEST(ContourTable, EmptyFullAndSingleCorner) {
    const auto& t = cell_cases();
    EXPECT_EQ(t[0].components, 0);
    EXPECT_EQ(t[255].components, 0);
    for (int c = 0; c < 8; ++c) {
        for (const int cfg : {1 << c, 255 ^ (1 << c)}) {
            EXPECT_EQ(t[cfg].components, 1) << cfg;
            int crossed = 0;
            for (int e = 0; e < 12; ++e) crossed += t[cfg].edge_component[e] >= 0 ? 1 : 0;
            EXPECT_EQ(crossed, 3) << cfg;
            EXPECT_EQ(t[cfg].merged_faces, 0) << cfg;
        }
    }
}

TEST(ContourTable, AmbiguousCasesFollowTheFaceRule) {
    const auto& t = cell_cases();
    // Two inside corners on a face diagonal: inside joins only along edges -> two components.
    EXPECT_EQ(t[config_of({0, 3})].components, 2);
    // Its complement: the two outside corners join across the ambiguous face -> one component.
    EXPECT_EQ(t[255 ^ config_of({0, 3})].components, 1);
    // Body diagonal, both ways round: never joined through the cell -> two components.
    EXPECT_EQ(t[config_of({0, 7})].components, 2);
    EXPECT_EQ(t[255 ^ config_of({0, 7})].components, 2);
    // Four inside corners in tetrahedral position (every face ambiguous): four isolated inside corners
    // around one outside group -> four components. The complement is the other tetrahedron.
    EXPECT_EQ(t[config_of({0, 3, 5, 6})].components, 4);
    EXPECT_EQ(t[config_of({1, 2, 4, 7})].components, 4);
    // Three inside corners around one corner's faces, e.g. {1, 2, 4}: three components.
    EXPECT_EQ(t[config_of({1, 2, 4})].components, 3);
    // Inside ring a, c (diagonal on face z = 0) joined over the top: one component touching face 4 twice.
    const int ring = config_of({0, 3, 4, 5, 7});
    EXPECT_EQ(t[ring].components, 1);
    EXPECT_EQ(t[ring].merged_faces, 1 << 4);
}

TEST(ContourTable, EveryConfigurationIsConsistent) {
    const auto& t = cell_cases();
    int max_components = 0;
    for (int cfg = 0; cfg < 256; ++cfg) {
        const CellCase& cc = t[cfg];
        max_components = std::max<int>(max_components, cc.components);
        std::array<int, kMaxComponents> uses{};
        for (int e = 0; e < 12; ++e) {
            const auto [c0, c1] = edge_corners(e);
            const bool crossed = ((cfg >> c0) & 1) != ((cfg >> c1) & 1);
            ASSERT_EQ(cc.edge_component[e] >= 0, crossed) << cfg << " edge " << e;
            if (crossed) {
                ASSERT_LT(cc.edge_component[e], cc.components);
                ++uses[cc.edge_component[e]];
            }
        }
        // Every component is a loop over at least three sign-change edges.
        for (int k = 0; k < cc.components; ++k) EXPECT_GE(uses[k], 3) << cfg;
        // A face that is not ambiguous has 0 or 2 sign-change edges, both in one component (one segment);
        // only ambiguous faces can be merged.
        for (int f = 0; f < 6; ++f) {
            if ((cc.merged_faces >> f) & 1) {
                EXPECT_TRUE(face_ambiguous(cfg, f)) << cfg;
            }
            if (face_ambiguous(cfg, f)) continue;
            int first = -1;
            for (int e = 0; e < 12; ++e) {
                const auto [c0, c1] = edge_corners(e);
                if (((c0 >> (f / 2)) & 1) != (f & 1) || ((c1 >> (f / 2)) & 1) != (f & 1)) continue;  // not on f
                if (cc.edge_component[e] < 0) continue;
                if (first < 0) first = cc.edge_component[e];
                EXPECT_EQ(cc.edge_component[e], first) << cfg << " face " << f;
            }
        }
    }
    EXPECT_EQ(max_components, kMaxComponents);
}

}  // namespace
}  // namespace tridex::compute::contour
