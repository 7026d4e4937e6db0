// shaders/dexel_contour_rays.glsl - part of dexel_contour.comp: the GPU tri-dexel slabs (bindings 0-14,
// layout of compute/gpu/gpu_dexel_slabs.hpp) and reading edge crossings from them (contour::edge_crossing).
// Needs pc.cells (the lattice's cells) declared by the including shader.

// Ray sets X, Y, Z: meta, inline depths, inline materials, pool depths, pool materials (gpu_dexel_slabs.hpp).
layout(std430, set = 0, binding = 0) readonly buffer M0 { uint meta0[]; };
layout(std430, set = 0, binding = 1) readonly buffer I0 { vec4 inl0[]; };
layout(std430, set = 0, binding = 2) readonly buffer J0 { uint inm0[]; };
layout(std430, set = 0, binding = 3) readonly buffer P0 { vec2 pool0[]; };
layout(std430, set = 0, binding = 4) readonly buffer Q0 { uint pom0[]; };
layout(std430, set = 0, binding = 5) readonly buffer M1 { uint meta1[]; };
layout(std430, set = 0, binding = 6) readonly buffer I1 { vec4 inl1[]; };
layout(std430, set = 0, binding = 7) readonly buffer J1 { uint inm1[]; };
layout(std430, set = 0, binding = 8) readonly buffer P1 { vec2 pool1[]; };
layout(std430, set = 0, binding = 9) readonly buffer Q1 { uint pom1[]; };
layout(std430, set = 0, binding = 10) readonly buffer M2 { uint meta2[]; };
layout(std430, set = 0, binding = 11) readonly buffer I2 { vec4 inl2[]; };
layout(std430, set = 0, binding = 12) readonly buffer J2 { uint inm2[]; };
layout(std430, set = 0, binding = 13) readonly buffer P2 { vec2 pool2[]; };
layout(std430, set = 0, binding = 14) readonly buffer Q2 { uint pom2[]; };
uint ray_meta(int a, uint r) { return a == 0 ? meta0[r] : (a == 1 ? meta1[r] : meta2[r]); }
// Interval i of ray r (meta m) of set a: depths and the end materials (enter | exit << 8).
void ray_interval(int a, uint r, uint m, uint i, out float en, out float ex, out uint mat) {
    uint n = m & 127u;
    if (n <= 2u) {
        vec4 d = a == 0 ? inl0[r] : (a == 1 ? inl1[r] : inl2[r]);
        uint mm = a == 0 ? inm0[r] : (a == 1 ? inm1[r] : inm2[r]);
        en = i == 0u ? d.x : d.z;
        ex = i == 0u ? d.y : d.w;
        mat = i == 0u ? (mm & 0xffffu) : (mm >> 16);
    } else {
        uint s = (m >> 11) * 8u + i;
        vec2 d = a == 0 ? pool0[s] : (a == 1 ? pool1[s] : pool2[s]);
        mat = a == 0 ? pom0[s] : (a == 1 ? pom1[s] : pom2[s]);
        en = d.x;
        ex = d.y;
    }
}

bool finite(float x) { return !isinf(x) && !isnan(x); }

// contour::edge_crossing: the crossing on the edge from node n along axis a, from that edge's own ray;
// `fallback` as EdgeCrossing::fallback (the ray has no end on the edge), `exit_end` as EdgeCrossing::exit.
double edge_crossing(int a, ivec3 n, bool start_inside, out uint mat, out bool fallback, out bool exit_end) {
    fallback = false;
    exit_end = false;
    int ua = (a + 1) % 3, va = (a + 2) % 3;
    uint r = uint(n[ua]) + uint(pc.cells[ua] + 1) * uint(n[va]);
    uint m = ray_meta(a, r), cnt = m & 127u;
    double lo_e = double(n[a]);
    double hi_e = lo_e + 1.0lf;
    bool found = false;
    double best = 0.0lf;
    uint best_mat = 0u;
    for (uint i = 0u; i < cnt; ++i) {
        float en, ex;
        uint pair;
        ray_interval(a, r, m, i, en, ex, pair);
        for (int side = 0; side < 2; ++side) {
            float ef = side == 0 ? en : ex;
            uint em = side == 0 ? (pair & 255u) : ((pair >> 8) & 255u);
            if (!finite(ef)) continue;
            double e = double(ef);
            if (e < lo_e) continue;
            if (e > hi_e) break;
            if (start_inside && side == 0 && e == lo_e) continue;  // the inside node's own enter
            if (start_inside) { mat = em; exit_end = side == 1; return e; }
            best = e;
            best_mat = em;
            exit_end = side == 1;
            found = true;
        }
        if (double(ex) > hi_e) break;
    }
    if (found) { mat = best_mat; return best; }
    fallback = true;
    exit_end = false;
    // The ray disagrees with the occupancy: nearest end within half a cell, clamped into the edge.
    double nearest_gap = 0.5lf;
    bool near = false;
    for (uint i = 0u; i < cnt; ++i) {
        float en, ex;
        uint pair;
        ray_interval(a, r, m, i, en, ex, pair);
        for (int side = 0; side < 2; ++side) {
            float ef = side == 0 ? en : ex;
            if (!finite(ef)) continue;
            double e = double(ef);
            precise double gap = e < lo_e ? lo_e - e : e - hi_e;
            if (gap <= nearest_gap) {
                nearest_gap = gap;
                best = e < lo_e ? lo_e : (hi_e < e ? hi_e : e);
                best_mat = side == 0 ? (pair & 255u) : ((pair >> 8) & 255u);
                exit_end = side == 1;
                near = true;
            }
        }
    }
    mat = near ? best_mat : 0u;
    return near ? best : lo_e + 0.5lf;
}


// The same without the fallback and kind flags.
double edge_crossing(int a, ivec3 n, bool start_inside, out uint mat) {
    bool fallback, exit_end;
    return edge_crossing(a, n, start_inside, mat, fallback, exit_end);
}
