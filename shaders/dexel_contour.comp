// shaders/dexel_contour.comp - manifold dual contouring of dirty tiles, read from the GPU tri-dexel slabs,
// into per-tile regions of vertex and index buffers plus one VkDrawIndexedIndirectCommand per tile.
// One workgroup = one tile of 16^3 cells. The method and the arithmetic are the CPU contourer's
// (compute/contour_tile.cpp, contour_sample.cpp) step for step, in double precision with contraction
// forbidden (precise), so vertex positions are bit for bit the CPU's doubles and the quad diagonals agree:
//  1. node occupancy of nodes c0-1 .. c0+17 from the X rays (enter <= x < exit; boundary nodes outside);
//  2. per own cell: sign-change edges (counted: 2 triangles each) mark the 4 cells around them as used;
//     a split face (contour_table.hpp merged_faces on both sides) near the tile flags it for the host;
//  3. used cells (c0-1 .. c1-1) get vertex slots (one per surface component) by a shared counter;
//  4. if the tile's region is too small, the needs are reported and nothing is written (the old mesh
//     stays drawable); otherwise each used component's vertex is placed at the mean of its crossings
//     (clamped into the cell), with the material of the nearest crossing;
//  5. each sign-change edge emits its quad, split along the shorter diagonal, with tile-local indices.
// Tiles are self-contained: vertices owned by neighbour tiles are recomputed (same bits) into this tile's
// region, so redoing one tile never invalidates another tile's indices.
#version 450

layout(local_size_x = 64) in;

const int T = 16;     // cells per tile side (TileGrid::kTileCells)
const int SPAN = 19;  // occupancy nodes per side (OccupancyBlock::kSpan)
const int CS = 17;    // cached cells per side: c0-1 .. c0+15
const uint NONE = 0xffffffffu;
const uint MARK = 0xfffffffeu;

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
// cell_cases(): x = components | merged_faces << 8; y = edges 0-7, z = edges 8-11, 4 bits each (component + 1).
layout(std430, set = 0, binding = 15) readonly buffer Cases { uvec4 cases[]; };
layout(std430, set = 0, binding = 16) readonly buffer Jobs { uint job_tile[]; };
layout(std430, set = 0, binding = 17) readonly buffer Regions { uvec4 region[]; };  // voff, vcap, ioff, icap
layout(std430, set = 0, binding = 18) writeonly buffer Status { uvec4 status[]; };  // state, vertices, indices, 0
struct Vertex { vec3 grid; uint material; };
layout(std430, set = 0, binding = 19) writeonly buffer Vertices { Vertex vtx[]; };
layout(std430, set = 0, binding = 20) coherent buffer VertexD { double vd[]; };     // 3 per vertex, grid units
layout(std430, set = 0, binding = 21) writeonly buffer Indices { uint idx[]; };
layout(std430, set = 0, binding = 22) writeonly buffer Commands { uint cmd[]; };     // 5 per tile

layout(push_constant) uniform Push {
    ivec4 cells;  // xyz: lattice cells
    ivec4 tiles;  // xyz: tiles per axis
    uint job_base;
} pc;

shared uint occ[SPAN * SPAN];
shared uint vbase[CS * CS * CS];
shared uint s_vcount, s_icount, s_flags, s_icursor;

ivec3 lo;   // node c0 - 1
ivec3 c0;
ivec3 c1;

ivec3 unit(int a) { ivec3 e = ivec3(0); e[a] = 1; return e; }

uint row(int j, int k) { return occ[(j - lo.y) + SPAN * (k - lo.z)]; }
bool inside(ivec3 n) { return ((row(n.y, n.z) >> uint(n.x - lo.x)) & 1u) != 0u; }
int config(ivec3 n) {
    uint b = uint(n.x - lo.x);
    int cfg = 0;
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy) cfg |= int((row(n.y + dy, n.z + dz) >> b) & 3u) << (2 * dy + 4 * dz);
    return cfg;
}
int components(int cfg) { return int(cases[cfg].x & 255u); }
uint merged(int cfg) { return (cases[cfg].x >> 8) & 255u; }
int edge_component(int cfg, int e) {
    uint w = e < 8 ? cases[cfg].y : cases[cfg].z;
    return int((w >> (4 * uint(e & 7))) & 15u) - 1;
}
uint cache_index(ivec3 cell) { ivec3 d = cell - lo; return uint(d.x + CS * (d.y + CS * d.z)); }

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

// contour::edge_crossing: the crossing on the edge from node n along axis a, from that edge's own ray.
double edge_crossing(int a, ivec3 n, bool start_inside, out uint mat) {
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
            if (start_inside) { mat = em; return e; }
            best = e;
            best_mat = em;
            found = true;
        }
        if (double(ex) > hi_e) break;
    }
    if (found) { mat = best_mat; return best; }
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
                near = true;
            }
        }
    }
    mat = near ? best_mat : 0u;
    return near ? best : lo_e + 0.5lf;
}

double dot3(dvec3 p) { precise double r = p.x * p.x + p.y * p.y + p.z * p.z; return r; }

bool face_split(ivec3 lower, int f) {
    uint below = merged(config(lower)) >> uint(2 * f + 1);
    uint above = merged(config(lower + unit(f))) >> uint(2 * f);
    return ((below & above) & 1u) != 0u;
}

// The vertices of used cell `cell` (TileContourer::cell_vertices) into slots base .. base + components - 1.
void place_vertices(ivec3 cell, uint base) {
    int cfg = config(cell);
    dvec3 sum[4] = dvec3[4](dvec3(0.0lf), dvec3(0.0lf), dvec3(0.0lf), dvec3(0.0lf));
    int count[4] = int[4](0, 0, 0, 0);
    dvec3 point[12];
    uint mat[12];
    int owner[12];
    int crossings = 0;
    for (int e = 0; e < 12; ++e) {
        int comp = edge_component(cfg, e);
        if (comp < 0) continue;
        int a = e / 4;
        ivec3 off = ivec3(0);
        off[(a + 1) % 3] = e & 1;
        off[(a + 2) % 3] = (e >> 1) & 1;
        int corner = off.x + 2 * off.y + 4 * off.z;
        ivec3 p = cell + off;
        uint m;
        double t = edge_crossing(a, p, ((cfg >> corner) & 1) != 0, m);
        dvec3 q = dvec3(p);
        q[a] = t;
        point[crossings] = q;
        mat[crossings] = m;
        owner[crossings] = comp;
        ++crossings;
        precise dvec3 s = sum[comp] + q;
        sum[comp] = s;
        ++count[comp];
    }
    dvec3 clo = dvec3(cell);
    int comps = components(cfg);
    dvec3 pos[4];
    uint best_mat[4];
    double best_d2[4];
    for (int c = 0; c < comps; ++c) {
        precise dvec3 mean = sum[c] / double(count[c]);
        pos[c] = min(max(mean, clo), clo + dvec3(1.0lf));
        best_d2[c] = -1.0lf;
        best_mat[c] = 0u;
    }
    for (int i = 0; i < crossings; ++i) {
        int c = owner[i];
        precise dvec3 d = point[i] - pos[c];
        double d2 = dot3(d);
        if (best_d2[c] < 0.0lf || d2 < best_d2[c] || (d2 == best_d2[c] && mat[i] > best_mat[c])) {
            best_d2[c] = d2;
            best_mat[c] = mat[i];
        }
    }
    uint voff = region[job_tile[pc.job_base + gl_WorkGroupID.x]].x;
    for (int c = 0; c < comps; ++c) {
        uint v = voff + base + uint(c);
        vtx[v].grid = vec3(pos[c]);
        vtx[v].material = best_mat[c];
        vd[3u * v] = pos[c].x;
        vd[3u * v + 1u] = pos[c].y;
        vd[3u * v + 2u] = pos[c].z;
    }
}

// The 4 cells around the edge from n along a, counter-clockwise seen from +a (TileContourer::emit_edge).
ivec3 ring_cell(ivec3 n, int a, int r) {
    const int db[4] = int[4](-1, 0, 0, -1);
    const int dc[4] = int[4](-1, -1, 0, 0);
    ivec3 c = n;
    c[(a + 1) % 3] += db[r];
    c[(a + 2) % 3] += dc[r];
    return c;
}
int ring_local_edge(int a, int r) {
    const int db[4] = int[4](-1, 0, 0, -1);
    const int dc[4] = int[4](-1, -1, 0, 0);
    return 4 * a + (-db[r]) + 2 * (-dc[r]);
}

// Own cell n (absolute) of local index i, or false when i lies beyond the lattice's last cell.
bool own_cell(uint i, out ivec3 n) {
    n = c0 + ivec3(int(i) % T, (int(i) / T) % T, int(i) / (T * T));
    return all(lessThan(n, c1));
}

void main() {
    uint job = pc.job_base + gl_WorkGroupID.x;
    uint tile = job_tile[job];
    ivec3 tc = ivec3(int(tile % uint(pc.tiles.x)), int((tile / uint(pc.tiles.x)) % uint(pc.tiles.y)),
                     int(tile / uint(pc.tiles.x * pc.tiles.y)));
    c0 = tc * T;
    c1 = min(c0 + ivec3(T), pc.cells.xyz);
    lo = c0 - ivec3(1);
    uint lid = gl_LocalInvocationIndex;
    if (lid == 0u) { s_vcount = 0u; s_icount = 0u; s_flags = 0u; s_icursor = 0u; }

    // 1. occupancy (OccupancyBlock::fill)
    int i_lo = max(1, lo.x), i_hi = min(pc.cells.x - 1, lo.x + SPAN - 1);
    for (uint w = lid; w < uint(SPAN * SPAN); w += 64u) {
        int j = lo.y + int(w) % SPAN, k = lo.z + int(w) / SPAN;
        uint mask = 0u;
        if (i_lo <= i_hi && j >= 1 && j <= pc.cells.y - 1 && k >= 1 && k <= pc.cells.z - 1) {
            uint r = uint(j) + uint(pc.cells.y + 1) * uint(k);
            uint m = meta0[r], cnt = m & 127u;
            for (uint i = 0u; i < cnt; ++i) {
                float en, ex;
                uint pair;
                ray_interval(0, r, m, i, en, ex, pair);
                if (!(en <= ex)) continue;
                float first = ceil(en), last = ceil(ex) - 1.0;
                if (last < float(i_lo)) continue;
                if (first > float(i_hi)) break;
                int b0 = int(max(first, float(i_lo))) - lo.x;
                int b1 = int(min(last, float(i_hi))) - lo.x;
                if (b0 > b1) continue;
                mask |= (2u << uint(b1)) - (1u << uint(b0));
            }
        }
        occ[w] = mask;
    }
    for (uint w = lid; w < uint(CS * CS * CS); w += 64u) vbase[w] = NONE;
    barrier();

    // 2. sign-change edges of own cells: count, mark the cells around them, look for split faces
    for (uint i = lid; i < uint(T * T * T); i += 64u) {
        ivec3 n;
        if (!own_cell(i, n)) continue;
        int cfg = config(n);
        if (cfg == 0 || cfg == 255) continue;
        bool in_n = inside(n);
        for (int f = 0; f < 3; ++f)
            if (n[f] >= 1 && face_split(n - unit(f), f)) atomicOr(s_flags, 1u);
        for (int a = 0; a < 3; ++a) {
            if (inside(n + unit(a)) == in_n) continue;
            int b = (a + 1) % 3, c = (a + 2) % 3;
            ivec3 ring[4];
            for (int r = 0; r < 4; ++r) {
                ring[r] = ring_cell(n, a, r);
                vbase[cache_index(ring[r])] = MARK;
            }
            if (face_split(ring[0], b) || face_split(ring[1], c) || face_split(ring[3], b) || face_split(ring[0], c))
                atomicOr(s_flags, 1u);
            atomicAdd(s_icount, 6u);
        }
    }
    barrier();

    // 3. vertex slots of the used cells
    for (uint w = lid; w < uint(CS * CS * CS); w += 64u) {
        if (vbase[w] != MARK) continue;
        ivec3 cell = lo + ivec3(int(w) % CS, (int(w) / CS) % CS, int(w) / (CS * CS));
        vbase[w] = atomicAdd(s_vcount, uint(components(config(cell))));
    }
    barrier();
    uvec4 reg = region[tile];
    uint flags = s_flags, vcount = s_vcount, icount = s_icount;
    if (flags != 0u || vcount > reg.y || icount > reg.w) {
        if (lid == 0u) status[job] = uvec4(flags != 0u ? 2u : 1u, vcount, icount, 0u);
        return;
    }

    // 4. vertices
    for (uint w = lid; w < uint(CS * CS * CS); w += 64u) {
        uint base = vbase[w];
        if (base == NONE) continue;
        place_vertices(lo + ivec3(int(w) % CS, (int(w) / CS) % CS, int(w) / (CS * CS)), base);
    }
    memoryBarrierBuffer();
    barrier();

    // 5. one quad per sign-change edge, split along the shorter diagonal, outward (TileContourer::emit_edge)
    for (uint i = lid; i < uint(T * T * T); i += 64u) {
        ivec3 n;
        if (!own_cell(i, n)) continue;
        int cfg = config(n);
        if (cfg == 0 || cfg == 255) continue;
        bool in_n = inside(n);
        for (int a = 0; a < 3; ++a) {
            if (inside(n + unit(a)) == in_n) continue;
            uint v[4];
            for (int r = 0; r < 4; ++r) {
                ivec3 cell = ring_cell(n, a, r);
                int comp = edge_component(config(cell), ring_local_edge(a, r));
                v[r] = vbase[cache_index(cell)] + uint(comp);
            }
            uint o[4];
            if (in_n) o = uint[4](v[0], v[1], v[2], v[3]);  // ring order has normal +a
            else o = uint[4](v[0], v[3], v[2], v[1]);

            dvec3 p[4];
            for (int r = 0; r < 4; ++r) {
                uint g = 3u * (reg.x + o[r]);
                p[r] = dvec3(vd[g], vd[g + 1u], vd[g + 2u]);
            }
            precise dvec3 d02 = p[0] - p[2];
            precise dvec3 d13 = p[1] - p[3];
            uint at = reg.z + atomicAdd(s_icursor, 6u);
            if (sqrt(dot3(d02)) <= sqrt(dot3(d13))) {
                idx[at] = o[0]; idx[at + 1u] = o[1]; idx[at + 2u] = o[2];
                idx[at + 3u] = o[0]; idx[at + 4u] = o[2]; idx[at + 5u] = o[3];
            } else {
                idx[at] = o[1]; idx[at + 1u] = o[2]; idx[at + 2u] = o[3];
                idx[at + 3u] = o[1]; idx[at + 4u] = o[3]; idx[at + 5u] = o[0];
            }
        }
    }
    if (lid == 0u) {
        cmd[5u * tile] = icount;
        cmd[5u * tile + 1u] = 1u;
        cmd[5u * tile + 2u] = reg.z;
        cmd[5u * tile + 3u] = reg.x;  // vertexOffset (int32; regions stay below 2^31)
        cmd[5u * tile + 4u] = 0u;
        status[job] = uvec4(0u, vcount, icount, 0u);
    }
}
