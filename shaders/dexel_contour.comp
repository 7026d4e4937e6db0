// shaders/dexel_contour.comp - manifold dual contouring of dirty tiles, read from the GPU tri-dexel slabs,
// into per-tile regions of vertex and index buffers plus one VkDrawIndexedIndirectCommand per tile.
// One workgroup = one tile of 16^3 cells. The method and the arithmetic are the CPU contourer's
// (compute/contour/contour_tile.cpp, contour_sample.cpp, contour_qef.cpp) step for step, in double precision with
// contraction forbidden (precise), so vertex positions are bit for bit the CPU's doubles and the quad
// diagonals agree:
//  1. node occupancy of nodes c0-1 .. c0+17 from the X rays (enter <= x < exit; boundary nodes outside);
//  2. per row of cached cells (32-bit masks skip uniform cells, as on the CPU): split faces between two
//     cached cells (contour_table.hpp merged_faces on both sides: tunnels thinner than a cell) go to a
//     face list; own cells' sign-change edges go to an edge list (2 triangles each) and mark the 4 cells
//     around them used; edges with a split face around them become fans (2b). More than FACE_CAP split
//     faces, or split faces with more than EDGE_CAP edges, flag the tile for the host (CPU contourer);
//  3. used cells (c0-1 .. c1-1) get vertex slots (one per surface component) by a shared counter and go
//     to a shared cell list (lists keep all 64 invocations busy in steps 4 and 5);
//  4. if the tile's region is too small, the needs are reported and nothing is written (the old mesh
//     stays drawable); otherwise each used component's vertex is placed by the QEF of its crossings and
//     their normals from the neighbouring rays (dexel_contour_qef.glsl, contour_qef.cpp: relative to the
//     mean of its crossings, minimised over the cell), with the material of the nearest crossing; the
//     normals read rays through nodes c0-2 .. c0+18 (c0-3 .. c0+19 for the corner fill's face-adjacent cells,
//     whose node occupancy is read from the X rays), and the one-sided slopes' gap check lines of the other ray
//     sets up to 3 nodes beyond a crossing's edge along its ray (bounds-checked, straight from the slabs); split faces
//     get one vertex per inside corner (the face QEF of that corner's two face-edge crossings, or their mean);
//  5. each sign-change edge emits its quad, split along the shorter diagonal, or, next to a split face, a
//     fan around its crossing point through the split faces' vertices; tile-local indices.
// Tiles are self-contained: vertices owned by neighbour tiles are recomputed (same bits) into this tile's
// region, so redoing one tile never invalidates another tile's indices.
#version 450
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require

const uint WG = 64u;  // invocations per workgroup
layout(local_size_x = WG) in;

const int T = 16;     // cells per tile side (TileGrid::kTileCells)
const int SPAN = 19;  // occupancy nodes per side (OccupancyBlock::kSpan)
const int CS = 17;    // cached cells per side: c0-1 .. c0+15
const int CELLS = CS * CS * CS;
const uint NONE16 = 0xffffu;          // vertex slot of an unused cell
const uint EDGE_CAP = 4096u;          // shared edge list entries; more -> step 5 scans the cells instead
const uint FACE_CAP = 128u;           // split faces a tile may hold on the GPU; more -> contoured on the host

// cell_cases(): x = components | merged_faces << 8; y = edges 0-7, z = edges 8-11, 4 bits each (component + 1).
layout(std430, set = 0, binding = 15) readonly buffer Cases { uvec4 cases[]; };
layout(std430, set = 0, binding = 16) readonly buffer Jobs { uint job_tile[]; };
layout(std430, set = 0, binding = 17) readonly buffer Regions { uvec4 region[]; };  // voff, vcap, ioff, icap
layout(std430, set = 0, binding = 18) writeonly buffer Status { uvec4 status[]; };  // state, vertices, indices, split faces
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

// 32 KiB of shared memory (lavapipe's limit): 16-bit entries, two per uint.
shared uint occ[SPAN * SPAN];
shared uint vslot[(CELLS + 1) / 2];     // per cached cell: first vertex slot, or NONE16 (step 2: 1 = used)
shared uint cell_list[(CELLS + 1) / 2]; // used cached cells (index into the 17^3 cache)
shared uint edge_list[EDGE_CAP / 2];    // own sign-change edges: local cell x + 16 y + 256 z | axis << 12 | fan << 15
shared uint face_list[FACE_CAP];        // split faces between cached cells: lower cell's cache index | f << 13
shared uint s_vcount, s_icount, s_flags, s_icursor, s_edges, s_faces, s_fans, s_face_base, s_fan_base, s_fan_cursor;
shared uint s_two;  // 2, read from shared memory so that no compiler unrolls probe_loop_cap's loop

// s_flags bits: 1 = the tile holds more split faces (or edges beside them) than the lists do; 2 = the loop cap hit.
const uint FLAG_LISTS = 1u, FLAG_LOOP_CAP = 2u;

// llvmpipe (lavapipe) ends every loop after its first pass once a SIMD group of invocations has taken 65535 loop
// iterations in one run of the shader, summed over all its loops (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS, a guard
// against endless loops); the rest of the tile's work is then silently skipped (vertices and indices left
// unwritten). Dense tiles get there (every crossing's normal loops over the intervals of four neighbour rays). The
// budget only shrinks, so a loop of two iterations run after the work tells whether it ran out: then it runs once.
// Flags the tile for the host (FLAG_LOOP_CAP).
void probe_loop_cap() {
    uint trips = 0u;
    [[dont_unroll]] for (uint i = 0u; i < s_two; ++i) trips += 1u;
    if (trips != s_two) atomicOr(s_flags, FLAG_LOOP_CAP);
}

uint get16(uint w, uint i) { return (w >> (16u * (i & 1u))) & 0xffffu; }
uint vbase(uint i) { return get16(vslot[i >> 1], i); }

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

#include "dexel_contour_rays.glsl"

double dot3(dvec3 p) { precise double r = p.x * p.x + p.y * p.y + p.z * p.z; return r; }

bool face_split(ivec3 lower, int f) {
    uint below = merged(config(lower)) >> uint(2 * f + 1);
    uint above = merged(config(lower + unit(f))) >> uint(2 * f);
    return ((below & above) & 1u) != 0u;
}

#include "dexel_contour_qef.glsl"
#include "dexel_contour_vertices.glsl"

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

// Step 2 for the sign-change edge from own node n along a: mark the cells around it, list it.
void note_edge(ivec3 n, int a) {
    ivec3 ring[4];
    for (int r = 0; r < 4; ++r) {
        ring[r] = ring_cell(n, a, r);
        uint ci = cache_index(ring[r]);
        atomicOr(vslot[ci >> 1], 1u << (16u * (ci & 1u)));
    }
    atomicAdd(s_icount, 6u);
    uint at = atomicAdd(s_edges, 1u);
    if (at < EDGE_CAP) {
        ivec3 l = n - c0;
        uint rec = uint(l.x + T * l.y + T * T * l.z) | (uint(a) << 12);
        atomicOr(edge_list[at >> 1], rec << (16u * (at & 1u)));
    }
}

// Step 5 for the sign-change edge from own node n along a (TileContourer::emit_edge without split faces).
void emit_edge(ivec3 n, int a, uvec4 reg) {
    bool in_n = inside(n);
    uint v[4];
    for (int r = 0; r < 4; ++r) {
        ivec3 cell = ring_cell(n, a, r);
        int comp = edge_component(config(cell), ring_local_edge(a, r));
        v[r] = vbase(cache_index(cell)) + uint(comp);
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

#include "dexel_contour_split.glsl"

void main() {
    uint job = pc.job_base + gl_WorkGroupID.x;
    uint tile = job_tile[job];
    ivec3 tc = ivec3(int(tile % uint(pc.tiles.x)), int((tile / uint(pc.tiles.x)) % uint(pc.tiles.y)),
                     int(tile / uint(pc.tiles.x * pc.tiles.y)));
    c0 = tc * T;
    c1 = min(c0 + ivec3(T), pc.cells.xyz);
    lo = c0 - ivec3(1);
    uint lid = gl_LocalInvocationIndex;
    if (lid == 0u) {
        s_vcount = 0u; s_icount = 0u; s_flags = 0u; s_icursor = 0u; s_edges = 0u;
        s_faces = 0u; s_fans = 0u; s_fan_cursor = 0u; s_two = 2u;
    }

    // 1. occupancy (OccupancyBlock::fill)
    int i_lo = max(1, lo.x), i_hi = min(pc.cells.x - 1, lo.x + SPAN - 1);
    for (uint w = lid; w < uint(SPAN * SPAN); w += WG) {
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
    for (uint w = lid; w < uint((CELLS + 1) / 2); w += WG) { vslot[w] = 0u; cell_list[w] = 0u; }
    for (uint w = lid; w < EDGE_CAP / 2u; w += WG) edge_list[w] = 0u;
    barrier();

    // 2. per row (j, k) of cached cells, the non-uniform ones (TileContourer::run's row masks): any split
    // face between two cached cells flags the tile (a superset of the faces the CPU would split for this
    // tile: its own cells' faces and the faces around its edges); own cells list their sign-change edges.
    int nx = c1.x - c0.x;
    uint range = (2u << uint(nx)) - 1u;  // bit b: the cell with min node lo.x + b, b = 0 .. nx
    for (uint w = lid; w < uint(CS * CS); w += WG) {
        int j = lo.y + int(w) % CS, k = lo.z + int(w) / CS;
        if (j >= c1.y || k >= c1.z) continue;
        uint r0 = row(j, k), r1 = row(j + 1, k), r2 = row(j, k + 1), r3 = row(j + 1, k + 1);
        uint any_in = r0 | r1 | r2 | r3, all_in = r0 & r1 & r2 & r3;
        uint uniform_cells = (~any_in & ~(any_in >> 1)) | (all_in & (all_in >> 1));
        uint todo = ~uniform_cells & range;
        bool own_row = j >= c0.y && k >= c0.z;
        while (todo != 0u) {
            int b = findLSB(todo);
            todo &= todo - 1u;
            ivec3 n = ivec3(lo.x + b, j, k);
            uint m = merged(config(n));
            if (m != 0u)
                for (int f = 0; f < 3; ++f)
                    if (((m >> uint(2 * f + 1)) & 1u) != 0u && n[f] + 1 < c1[f] && face_split(n, f)) {
                        uint at = atomicAdd(s_faces, 1u);
                        if (at < FACE_CAP) face_list[at] = cache_index(n) | (uint(f) << 13);
                        else atomicOr(s_flags, FLAG_LISTS);
                    }
            if (!own_row || b == 0) continue;
            bool in_n = inside(n);
            for (int a = 0; a < 3; ++a)
                if (inside(n + unit(a)) != in_n) note_edge(n, a);
        }
    }
    barrier();

    // 2b. with split faces (tunnels thinner than a cell): an edge with a split face around it becomes a fan
    // around its crossing point through the faces' segment vertices (TileContourer::emit_edge); count them.
    uint nfaces = min(s_faces, FACE_CAP);
    if (nfaces > 0u) {
        if (s_edges > EDGE_CAP) {
            if (lid == 0u) atomicOr(s_flags, FLAG_LISTS);  // no edge list to mark fans in: the host contours this tile
        } else {
            for (uint i = lid; i < s_edges; i += WG) {
                uint rec = get16(edge_list[i >> 1], i), l = rec & 4095u;
                ivec3 n = c0 + ivec3(int(l) % T, (int(l) / T) % T, int(l) / (T * T));
                int a = int((rec >> 12) & 3u);
                uint split = 0u;
                for (int r = 0; r < 4; ++r) {
                    ivec3 lower;
                    int g;
                    ring_face(n, a, r, lower, g);
                    split += face_index_of(lower, g) != NONE16 ? 1u : 0u;
                }
                if (split == 0u) continue;
                atomicOr(edge_list[i >> 1], 1u << (16u * (i & 1u) + 15u));
                atomicAdd(s_fans, 1u);
                atomicAdd(s_icount, 3u * (4u + split) - 6u);
            }
        }
    }
    barrier();

    // 3. vertex slots and the list of the used cells (both halves of a word by one invocation)
    for (uint w = lid; w < uint((CELLS + 1) / 2); w += WG) {
        uint word = vslot[w], out_word = 0u;
        for (uint h = 0u; h < 2u; ++h) {
            uint ci = 2u * w + h;
            uint slot = NONE16;
            if (ci < uint(CELLS) && get16(word, h) != 0u) {
                ivec3 cell = lo + ivec3(int(ci) % CS, (int(ci) / CS) % CS, int(ci) / (CS * CS));
                // One atomic for both counters: vertices in bits 0-15 (< 4 x 17^3), cells in bits 16-31.
                uint both = atomicAdd(s_vcount, uint(components(config(cell))) | (1u << 16));
                slot = both & 0xffffu;
                uint at = both >> 16;
                atomicOr(cell_list[at >> 1], ci << (16u * (at & 1u)));
            }
            out_word |= slot << (16u * h);
        }
        vslot[w] = out_word;
    }
    if (lid == 0u) {  // 4 slots per split face (its inside corners' segment vertices), 1 per fan centre
        s_face_base = atomicAdd(s_vcount, 4u * nfaces) & 0xffffu;
        s_fan_base = atomicAdd(s_vcount, s_fans) & 0xffffu;
    }
    probe_loop_cap();  // the counts above are complete only if no loop was cut short
    barrier();
    uvec4 reg = region[tile];
    uint flags = s_flags, vcount = s_vcount & 0xffffu, icount = s_icount, ncells = s_vcount >> 16, nedges = s_edges;
    if (flags != 0u || vcount > reg.y || icount > reg.w) {
        // State 1: the region is too small; 2: the host contours the tile (lists full); 3: the same (loop cap).
        uint state = (flags & FLAG_LOOP_CAP) != 0u ? 3u : (flags != 0u ? 2u : 1u);
        if (lid == 0u) status[job] = uvec4(state, vcount, icount, 0u);
        return;
    }

    // 4. vertices of the used cells
    for (uint i = lid; i < ncells; i += WG) {
        uint ci = get16(cell_list[i >> 1], i);
        place_vertices(lo + ivec3(int(ci) % CS, (int(ci) / CS) % CS, int(ci) / (CS * CS)), vbase(ci));
    }
    for (uint i = lid; i < nfaces; i += WG) place_face_vertices(i, reg.x + s_face_base + 4u * i);
    memoryBarrierBuffer();
    barrier();

    // 5. one quad per sign-change edge, split along the shorter diagonal, outward
    if (nedges <= EDGE_CAP) {
        for (uint i = lid; i < nedges; i += WG) {
            uint rec = get16(edge_list[i >> 1], i);
            uint l = rec & 4095u;
            ivec3 n = c0 + ivec3(int(l) % T, (int(l) / T) % T, int(l) / (T * T));
            if ((rec >> 15) != 0u) emit_fan(n, int((rec >> 12) & 3u), reg);
            else emit_edge(n, int((rec >> 12) & 3u), reg);
        }
    } else {  // the list overflowed: scan the own cells
        for (uint i = lid; i < uint(T * T * T); i += WG) {
            ivec3 n;
            if (!own_cell(i, n)) continue;
            int cfg = config(n);
            if (cfg == 0 || cfg == 255) continue;
            bool in_n = inside(n);
            for (int a = 0; a < 3; ++a)
                if (inside(n + unit(a)) != in_n) emit_edge(n, a, reg);
        }
    }
    probe_loop_cap();  // every vertex and index was written only if no loop was cut short
    barrier();
    if (lid == 0u && (s_flags & FLAG_LOOP_CAP) != 0u) status[job] = uvec4(3u, vcount, icount, 0u);
    if (lid == 0u && (s_flags & FLAG_LOOP_CAP) == 0u) {
        cmd[5u * tile] = icount;
        cmd[5u * tile + 1u] = 1u;
        cmd[5u * tile + 2u] = reg.z;
        cmd[5u * tile + 3u] = reg.x;  // vertexOffset (int32; regions stay below 2^31)
        cmd[5u * tile + 4u] = 0u;
        status[job] = uvec4(0u, vcount, icount, nfaces);
    }
}
