// compute/contour/contour_table.cpp - builds the 256-entry cell component table programmatically.
#include "compute/contour/contour_table.hpp"

#include <cstdio>
#include <cstdlib>
#include <utility>

namespace tridex::compute::contour {
namespace {

int corner_axis_offset(int c, int axis) { return (c >> axis) & 1; }

int corner_from_offsets(int ox, int oy, int oz) { return ox | (oy << 1) | (oz << 2); }

/// Union-find over the 8 corners of one cell.
struct CornerSets {
    std::array<int, 8> parent{0, 1, 2, 3, 4, 5, 6, 7};
    int find(int c) {
        while (parent[c] != c) c = parent[c] = parent[parent[c]];
        return c;
    }
    void unite(int a, int b) { parent[find(a)] = find(b); }
};

CellCase build_case(int config) {
    auto inside = [config](int c) { return ((config >> c) & 1) != 0; };
    CornerSets sets;
    for (int e = 0; e < 12; ++e) {
        const auto [c0, c1] = edge_corners(e);
        if (inside(c0) == inside(c1)) sets.unite(c0, c1);  // both inside or both outside
    }
    for (int f = 0; f < 6; ++f) {
        if (!face_ambiguous(config, f)) continue;
        const auto q = face_corners(f);
        // Corners 0 and 3 of a face are one diagonal, 1 and 2 the other; join the outside pair.
        if (inside(q[0])) sets.unite(q[1], q[2]);
        else sets.unite(q[0], q[3]);
    }
    CellCase cc;
    cc.edge_component.fill(-1);
    std::array<std::pair<int, int>, 12> pairs{};  // (inside group, outside group) of each component
    for (int e = 0; e < 12; ++e) {
        const auto [c0, c1] = edge_corners(e);
        if (inside(c0) == inside(c1)) continue;
        const std::pair<int, int> key = inside(c0) ? std::pair{sets.find(c0), sets.find(c1)}
                                                   : std::pair{sets.find(c1), sets.find(c0)};
        int id = 0;
        while (id < cc.components && pairs[id] != key) ++id;
        if (id == cc.components) pairs[cc.components++] = key;
        cc.edge_component[e] = static_cast<std::int8_t>(id);
    }
    if (cc.components > kMaxComponents) {
        std::fprintf(stderr, "contour_table: configuration %d has %d components\n", config, cc.components);
        std::abort();  // cannot happen: a cube holds at most four separate corner groups
    }
    for (int f = 0; f < 6; ++f) {
        if (!face_ambiguous(config, f)) continue;
        const auto q = face_corners(f);
        // The two segments cut off the two inside corners; each segment's component is that of either
        // face edge touching its inside corner. Face edges: q0-q1, q2-q3 (axis 1) and q0-q2, q1-q3 (axis 2).
        const int a = f / 2, ax1 = (a + 1) % 3;
        auto face_edge = [ax1](int p, int r) {
            // Cube edge joining corners p and r that differ along one axis.
            const int axis = (p ^ r) == (1 << ax1) ? ax1 : (ax1 + 1) % 3;
            const int lo = p < r ? p : r;
            const int ob = corner_axis_offset(lo, (axis + 1) % 3), oc = corner_axis_offset(lo, (axis + 2) % 3);
            return 4 * axis + ob + 2 * oc;
        };
        const int in_a = inside(q[0]) ? q[0] : q[1];
        const int in_b = inside(q[0]) ? q[3] : q[2];
        const int comp_a = cc.edge_component[face_edge(in_a, inside(q[0]) ? q[1] : q[0])];
        const int comp_b = cc.edge_component[face_edge(in_b, inside(q[0]) ? q[1] : q[0])];
        if (comp_a == comp_b) cc.merged_faces = static_cast<std::uint8_t>(cc.merged_faces | (1u << f));
    }
    return cc;
}

}  // namespace

std::array<int, 2> edge_corners(int e) {
    const int a = e / 4, ob = e & 1, oc = (e >> 1) & 1;
    int o0[3], o1[3];
    o0[a] = 0;
    o1[a] = 1;
    o0[(a + 1) % 3] = o1[(a + 1) % 3] = ob;
    o0[(a + 2) % 3] = o1[(a + 2) % 3] = oc;
    return {corner_from_offsets(o0[0], o0[1], o0[2]), corner_from_offsets(o1[0], o1[1], o1[2])};
}

std::array<int, 4> face_corners(int f) {
    const int a = f / 2, side = f & 1;
    std::array<int, 4> q{};
    for (int idx = 0; idx < 4; ++idx) {
        int o[3];
        o[a] = side;
        o[(a + 1) % 3] = idx & 1;
        o[(a + 2) % 3] = (idx >> 1) & 1;
        q[idx] = corner_from_offsets(o[0], o[1], o[2]);
    }
    return q;
}

bool face_ambiguous(int config, int f) {
    const auto q = face_corners(f);
    auto in = [config](int c) { return ((config >> c) & 1) != 0; };
    return in(q[0]) == in(q[3]) && in(q[1]) == in(q[2]) && in(q[0]) != in(q[1]);
}

const std::array<CellCase, 256>& cell_cases() {
    static const std::array<CellCase, 256> table = [] {
        std::array<CellCase, 256> t{};
        for (int config = 0; config < 256; ++config) t[config] = build_case(config);
        return t;
    }();
    return table;
}

}  // namespace tridex::compute::contour
