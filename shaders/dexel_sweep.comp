// shaders/dexel_sweep.comp - swept-volume Booleans (subtract, union, paint) on the three tri-dexel ray sets.
// A tile is TILE_U x TILE_V = 8 rays of one ray set (its tile entry names it); a workgroup of 8 invocations
// takes the dispatch's tiles in turn (tiles gl_WorkGroupID.x, + gl_NumWorkGroups.x, ...), and for each tile
// every invocation loads its ray's intervals, applies the
// batch's sweeps that cover its node, in order, and writes the ray back (inline slots, or a region of
// the spill pool). The arithmetic is the CPU reference's (compute/tools/sweep.cpp, compute/tools/capsule.cpp,
// compute/model/interval_ops.cpp) step for step, with contraction forbidden (precise), so results match.
// Mesh tools (kind 2): at each pose the ray reads the nearest ray of the tool's own dexels (ToolData,
// binding 9) and applies each of its intervals (compute/tools/sweep.cpp mesh_stamp_spans).
// A ray that needs more than MAXI intervals, or a pool region when the pool is full, is left unwritten
// and listed for the host (compute/gpu/gpu_sculptor.cpp), which compacts or grows the pool and redoes it.
// So is a ray whose loops the device cut short (llvmpipe's loop cap, below; listed with RETRY_LOOP_CAP), and the
// tiles a workgroup never reached (no mark in the done words after the tile entries); the host redoes those from
// its copy of the model as it was before the batch.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require

// One workgroup = 8 invocations = one tile of TILE_U x TILE_V rays at a time (TILE_U: specialisation constant
// 1, compute/gpu/gpu_sculptor.cpp kTileU), one SIMD row of llvmpipe. Each row of 8 lanes loops over all the
// tile's sweeps and a lane outside a sweep's footprint costs as much as one inside, so tiles are small. A
// workgroup loops over many tiles: llvmpipe pays a fixed cost to enter and leave each workgroup, so the host
// dispatches a few workgroups per driver thread rather than one per tile.
layout(local_size_x = 8) in;
layout(constant_id = 1) const uint TILE_U = 8u;
const uint TILE_V = 8u / TILE_U;

const uint MAXI = 16u;   // intervals a ray may hold in this kernel (longer rays go to the host)
const uint INLINE = 2u;  // intervals stored in the ray's own slots
const uint K = 3u;       // intervals the register path holds (rays with more take the array path)

struct GridSweep {       // compute/tools/sweep.hpp GridSweep, 96 bytes
    ivec3 lo; uint code;
    ivec3 hi; uint stamps;
    ivec3 origin; float radius;
    vec3 start; uint tool;  // kMesh: index into the tool table (ToolData)
    vec3 delta; float pad1;
    vec3 shank; float pad2;
};

// The three ray sets' slabs (compute/gpu/gpu_dexel_slabs.hpp), as arrays of 3 bindings indexed by the
// workgroup's ray set AX (the same for every invocation of a workgroup, so dynamically uniform).
layout(std430, set = 0, binding = 0) buffer Meta { uint v[]; } slab_meta[3];          // count | cap_chunks << 7 | off_chunk << 11
layout(std430, set = 0, binding = 1) buffer InlineDepth { vec4 v[]; } slab_inl[3];    // enter0, exit0, enter1, exit1
layout(std430, set = 0, binding = 2) buffer InlineMat { uint v[]; } slab_inl_mat[3];  // bytes: enter0, exit0, enter1, exit1
layout(std430, set = 0, binding = 3) buffer PoolDepth { vec2 v[]; } slab_pool[3];     // (enter, exit) per interval
layout(std430, set = 0, binding = 4) buffer PoolMat { uint v[]; } slab_pool_mat[3];   // enter | exit << 8
// The batch's sweeps in a uniform buffer: llvmpipe loads uniform-buffer words with a vector gather, but
// storage-buffer words one lane at a time (each with its own branch and bounds check), which cost more
// than all the chord arithmetic. MAX_SWEEPS (specialisation constant 2) = compute/gpu/gpu_sculptor.cpp max_sweeps_.
layout(constant_id = 2) const uint MAX_SWEEPS = 682u;
layout(std140, set = 0, binding = 5) uniform Sweeps { GridSweep sweeps[MAX_SWEEPS]; };
// Tile u | ray set << 30, tile v, first, count: the batch's tiles of all three sets, in one dispatch
// (tiles[0, tile_count)); then one done word per tile, four to an entry (tile t: tiles[tile_count + t / 4][t % 4]),
// zero on entry, set to 1 once the tile's workgroup has finished it.
layout(std430, set = 0, binding = 6) buffer Tiles { uvec4 tiles[]; };
layout(std430, set = 0, binding = 7) readonly buffer SweepIndex { uint sweep_index[]; };
layout(std430, set = 0, binding = 8) buffer Counters {  // one per ray set
    uint pool_head;      // chunks of 8 intervals handed out
    uint retry_count;    // rays listed in retry[]
    uint changed_rays;   // rays written back
    uint pad;
    uint retry[];
} counters[3];
// Mesh tools (compute/gpu/gpu_sculptor.cpp pack_tools): [t] = block of tool t; block: k (float bits), then per
// ray set nu, nv, ref_u, ref_v, word of the `first` offsets, word of the depths (float bits, 2 per interval).
layout(std430, set = 0, binding = 9) readonly buffer ToolData { uint tool_data[]; };

// False compiles the mesh-tool path out (compute/gpu/gpu_sculptor.cpp uses that variant for batches without
// kMesh sweeps; the result is the same, the kernel smaller).
layout(constant_id = 0) const bool HAS_MESH = true;
// The operations and tool kinds the batch holds (compute/gpu/gpu_sculptor.cpp picks a pipeline per pair):
// OPS bit 0 = subtract, 1 = union, 2 = paint; KINDS bit 0 = ball, 1 = flat end (kMesh: HAS_MESH, all
// bits set). llvmpipe runs both sides of every branch, so code for absent operations and tools costs
// time; with these constants it is compiled out.
layout(constant_id = 3) const uint OPS = 7u;
layout(constant_id = 4) const uint KINDS = 3u;

// Per ray set: rays along u and v, pool capacity (chunks) and the lattice's cells along the set's axis
// (union chords are clipped to [0, depth_cells]); compute/gpu/gpu_sculptor.cpp SetPush.
struct SetConstants {
    int nu;
    int nv;
    uint pool_chunks;
    float depth_cells;
};
layout(push_constant) uniform Push {
    SetConstants sets[3];
    uint tile_count;      // entries of tiles[]: workgroup w takes tiles w, w + gl_NumWorkGroups.x, ...
    uint retry_capacity;  // entries of each set's retry[]
    uint two;             // 2: probe_loop_cap's trip count, unknown to the compiler so that it stays a loop
} pc;

// Retry entries: the ray's index in its set, with this bit set when the loop cap cut its loops short.
const uint RETRY_LOOP_CAP = 0x80000000u;

// llvmpipe (lavapipe) ends every loop after its first pass once a SIMD group of invocations has taken 65535 loop
// iterations in one run of the shader, summed over all its loops (gallivm's LP_MAX_TGSI_LOOP_ITERATIONS, a guard
// against endless loops), without any error: a ray's sweeps would be skipped or its write-back cut. The host keeps
// each workgroup's tiles under that count by its own bound (compute/gpu/gpu_sculptor.cpp), but a single tile of
// many long sweeps can exceed it. The budget only shrinks, so a loop of two iterations run after the work tells
// whether it ran out: then it runs once. True when it did.
bool loop_cap_spent() {
    uint trips = 0u;
    [[dont_unroll]] for (uint i = 0u; i < pc.two; ++i) trips += 1u;
    return trips != pc.two;
}

// The workgroup's ray set (its tile's) and that set's constants, set first thing in main().
int AX;
int NU;
int NV;
uint POOL_CHUNKS;
float DEPTH_CELLS;

float en[MAXI];
float ex[MAXI];
uint mt[MAXI];  // enter material | exit material << 8
uint n;

// ---- chords (compute/tools/capsule.cpp) ----
float dot3(vec3 p, vec3 q) { precise float r = p.x * q.x + p.y * q.y + p.z * q.z; return r; }
vec3 cross3(vec3 p, vec3 q) {
    precise vec3 r = vec3(p.y * q.z - p.z * q.y, p.z * q.x - p.x * q.z, p.x * q.y - p.y * q.x);
    return r;
}

void add_ball(vec3 o, vec3 d, float dd, vec3 c, float r, inout float lo, inout float hi) {
    precise vec3 m = o - c;
    vec3 md = cross3(m, d);
    precise float disc = dd * (r * r) - dot3(md, md);
    if (disc < 0.0) return;
    precise float mid = -dot3(m, d) / dd;
    precise float half_len = sqrt(disc) / dd;
    precise float a = mid - half_len;
    precise float b = mid + half_len;
    lo = min(lo, a);
    hi = max(hi, b);
}

void add_cylinder(vec3 o, vec3 d, vec3 a, vec3 e, float ee, float r, inout float lo, inout float hi) {
    precise vec3 m = o - a;
    vec3 me = cross3(m, e);
    vec3 de = cross3(d, e);
    float qa = dot3(de, de);
    float qb = dot3(me, de);
    precise float qc = dot3(me, me) - ee * (r * r);
    float ms = dot3(m, e);
    float ds = dot3(d, e);
    precise float c0, c1;
    if (qa > 0.0) {
        precise float disc = qb * qb - qa * qc;
        if (disc < 0.0) return;
        precise float s = sqrt(disc);
        c0 = (-qb - s) / qa;
        c1 = (-qb + s) / qa;
    } else {
        if (qc > 0.0) return;
        c0 = -1.0 / 0.0;
        c1 = 1.0 / 0.0;
    }
    if (ds != 0.0) {
        precise float ta = -ms / ds;
        precise float tb = (ee - ms) / ds;
        c0 = max(c0, min(ta, tb));
        c1 = min(c1, max(ta, tb));
    } else if (ms < 0.0 || ms > ee) {
        return;
    }
    if (!(c0 <= c1)) return;
    lo = min(lo, c0);
    hi = max(hi, c1);
}

// compute/tools/capsule.cpp add_cap_path
void add_cap_path(vec3 p, vec3 g, float rr, float tc, float k, inout float lo, inout float hi) {
    float ga = dot3(g, g);
    float gb = dot3(p, g);
    precise float gc = dot3(p, p) - rr;
    precise float l0 = 0.0, l1 = 1.0;
    if (ga > 0.0) {
        precise float disc = gb * gb - ga * gc;
        if (!(disc >= 0.0)) return;
        precise float s = sqrt(disc);
        precise float r0 = (-gb - s) / ga;
        precise float r1 = (-gb + s) / ga;
        if (!(r0 <= 1.0 && r1 >= 0.0)) return;
        l0 = max(l0, r0);
        l1 = min(l1, r1);
    } else if (!(gc <= 0.0)) {
        return;
    }
    precise float ta = tc + l0 * k;
    precise float tb = tc + l1 * k;
    lo = min(lo, min(ta, tb));
    hi = max(hi, max(ta, tb));
}

// compute/tools/capsule.cpp add_cap_line
void add_cap_line(vec3 p, vec3 g, float rr, float lc, float kl, inout float lo, inout float hi) {
    float ga = dot3(g, g);
    float gb = dot3(p, g);
    precise float gc = dot3(p, p) - rr;
    precise float t0 = -1.0 / 0.0, t1 = 1.0 / 0.0;
    if (ga > 0.0) {
        precise float disc = gb * gb - ga * gc;
        if (!(disc >= 0.0)) return;
        precise float s = sqrt(disc);
        t0 = (-gb - s) / ga;
        t1 = (-gb + s) / ga;
    } else if (!(gc <= 0.0)) {
        return;
    }
    if (kl != 0.0) {
        precise float ta = (0.0 - lc) / kl;
        precise float tb = (1.0 - lc) / kl;
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
    } else if (!(lc >= 0.0 && lc <= 1.0)) {
        return;
    }
    if (!(t0 <= t1)) return;
    lo = min(lo, t0);
    hi = max(hi, t1);
}

// compute/tools/capsule.cpp add_cap
void add_cap(vec3 A, vec3 B, vec3 C, float ms, float ds, float cs, float c, float rr, inout float lo, inout float hi) {
    if (abs(ds) >= abs(cs)) {
        if (ds == 0.0) return;
        precise float tc = (c - ms) / ds;
        precise float k = cs / ds;
        precise vec3 p = A + B * tc;
        precise vec3 g = B * k - C;
        add_cap_path(p, g, rr, tc, k, lo, hi);
    } else {
        precise float lc = (ms - c) / cs;
        precise float kl = ds / cs;
        precise vec3 p = A - C * lc;
        precise vec3 g = B - C * kl;
        add_cap_line(p, g, rr, lc, kl, lo, hi);
    }
}

// compute/tools/capsule.cpp swept_cylinder_chord (the extent in t, accumulated into lo, hi)
void add_swept_cylinder(vec3 o, vec3 d, vec3 e, vec3 delta, float r, inout float lo, inout float hi) {
    float dd = dot3(d, d);
    float ee = dot3(e, e);
    if (!(dd > 0.0) || !(ee > 0.0) || !(r > 0.0)) return;
    precise float len = sqrt(ee);
    precise vec3 n = e / len;
    precise float rr = r * r;
    vec3 A = cross3(o, n);
    vec3 B = cross3(d, n);
    vec3 C = cross3(delta, n);
    float ms = dot3(o, n);
    float ds = dot3(d, n);
    float cs = dot3(delta, n);
    if (ds == 0.0 && cs == 0.0 && (ms < 0.0 || ms > len)) return;
    add_cylinder(o, d, vec3(0.0), e, ee, r, lo, hi);
    add_cylinder(o, d, delta, e, ee, r, lo, hi);
    add_cap(A, B, C, ms, ds, cs, 0.0, rr, lo, hi);
    add_cap(A, B, C, ms, ds, cs, len, rr, lo, hi);
    float cc = dot3(C, C);
    vec3 U = cross3(A, C);
    vec3 V = cross3(B, C);
    float vv = dot3(V, V);
    if (cc > 0.0 && vv > 0.0) {
        float ub = dot3(U, V);
        precise float uc = dot3(U, U) - cc * rr;
        precise float disc = ub * ub - vv * uc;
        if (disc >= 0.0) {
            precise float s = sqrt(disc);
            float ca = dot3(C, A);
            float cb = dot3(C, B);
            for (int side = 0; side < 2; ++side) {
                precise float t = side == 0 ? (-ub - s) / vv : (-ub + s) / vv;
                precise float l = (ca + t * cb) / cc;
                precise float h = ms + t * ds - l * cs;
                if (l >= 0.0 && l <= 1.0 && h >= 0.0 && h <= len) {
                    lo = min(lo, t);
                    hi = max(hi, t);
                }
            }
        }
    }
}

// compute/tools/sweep.cpp sweep_chord
bool sweep_chord(GridSweep s, int u, int v, uint stamp, out float d0, out float d1) {
    int ua = (AX + 1) % 3, va = (AX + 2) % 3;
    vec3 o = vec3(0.0), d = vec3(0.0);
    d[AX] = 1.0;
    precise float ou = float(u - s.origin[ua]) - s.start[ua];
    precise float ov = float(v - s.origin[va]) - s.start[va];
    o[ua] = ou;
    o[va] = ov;
    float lo = 1.0 / 0.0, hi = -1.0 / 0.0;
    float dd = dot3(d, d);
    uint kind = (s.code >> 8) & 0xffu;
    if (KINDS == 1u || (KINDS != 2u && kind == 0u)) {
        if (!(s.radius > 0.0)) return false;
        add_ball(o, d, dd, vec3(0.0), s.radius, lo, hi);
        float ee = dot3(s.delta, s.delta);
        if (ee > 0.0) {
            add_ball(o, d, dd, s.delta, s.radius, lo, hi);
            add_cylinder(o, d, vec3(0.0), s.delta, ee, s.radius, lo, hi);
        }
    } else {
        add_swept_cylinder(o, d, s.shank, s.delta, s.radius, lo, hi);
    }
    if (!(lo <= hi)) return false;
    precise float base = float(s.origin[AX]) + s.start[AX];
    d0 = base + lo;
    d1 = base + hi;
    return true;
}

#include "dexel_sweep_spans.glsl"

#include "dexel_sweep_registers.glsl"

void list_for_retry(uint ray) {
    uint k = atomicAdd(counters[AX].retry_count, 1u);
    if (k < pc.retry_capacity) counters[AX].retry[k] = ray;
}

// A kMesh sweep's lookup state for one ray: its tool's header for this ray set and the ray's offset from
// the tool start (compute/tools/sweep.cpp mesh_stamp_spans, step for step).
struct MeshRay {
    float kf, ou, ov, base;
    int tnu, tnv, rfu, rfv;
    uint fw, dw;
};

MeshRay mesh_ray(GridSweep s, int u, int v) {
    int ua = (AX + 1) % 3, va = (AX + 2) % 3;
    uint tb = tool_data[s.tool];
    uint hb = tb + 1u + 6u * uint(AX);
    MeshRay r;
    r.kf = uintBitsToFloat(tool_data[tb]);
    r.tnu = int(tool_data[hb]);
    r.tnv = int(tool_data[hb + 1u]);
    r.rfu = int(tool_data[hb + 2u]);
    r.rfv = int(tool_data[hb + 3u]);
    r.fw = tool_data[hb + 4u];
    r.dw = tool_data[hb + 5u];
    precise float ou = float(u - s.origin[ua]) - s.start[ua];
    precise float ov = float(v - s.origin[va]) - s.start[va];
    precise float base = float(s.origin[AX]) + s.start[AX];
    r.ou = ou;
    r.ov = ov;
    r.base = base;
    return r;
}

// The tool intervals [q0, q1) that stamp `st` of a kMesh sweep puts on the ray, and the stamp's depth
// offset ca; false when the ray misses the tool's grid at that stamp.
bool mesh_stamp(GridSweep s, MeshRay r, uint st, out uint q0, out uint q1, out float ca) {
    int ua = (AX + 1) % 3, va = (AX + 2) % 3;
    q0 = 0u;
    q1 = 0u;
    ca = 0.0;
    precise float f = s.stamps > 1u ? float(st) / float(s.stamps - 1u) : 0.0;
    precise vec3 c = s.delta * f;
    precise float xu = r.ou - c[ua];
    precise float xv = r.ov - c[va];
    precise float su = xu * r.kf;
    precise float sv = xv * r.kf;
    precise float fu = floor(su + 0.5);
    precise float fv = floor(sv + 0.5);
    if (!(fu >= float(-r.rfu)) || !(fu < float(r.tnu - r.rfu))) return false;
    if (!(fv >= float(-r.rfv)) || !(fv < float(r.tnv - r.rfv))) return false;
    uint tr = uint(int(fu) + r.rfu) + uint(r.tnu) * uint(int(fv) + r.rfv);
    q0 = tool_data[r.fw + tr];
    q1 = tool_data[r.fw + tr + 1u];
    ca = c[AX];
    return true;
}

// Applies the batch's sweeps to this invocation's ray of tile entry `t`, writes it back and counts it (or
// lists it for the host).
void sculpt_tile(uint t) {
    uvec4 tile = tiles[t];
    AX = int(tile.x >> 30);
    tile.x &= 0x3fffffffu;
    NU = pc.sets[AX].nu;
    NV = pc.sets[AX].nv;
    POOL_CHUNKS = pc.sets[AX].pool_chunks;
    DEPTH_CELLS = pc.sets[AX].depth_cells;
    int u = int(tile.x * TILE_U + gl_LocalInvocationID.x % TILE_U);
    int v = int(tile.y * TILE_V + gl_LocalInvocationID.x / TILE_U);
    if (u >= NU || v >= NV) return;
    uint ray = uint(u) + uint(NU) * uint(v);
    uint m = slab_meta[AX].v[ray];
    n = m & 127u;
    if (n > MAXI) { list_for_retry(ray); return; }
    int ua = (AX + 1) % 3, va = (AX + 2) % 3;
    bool changed = false;
    // The register path (batches without mesh tools, rays of at most K intervals): applies the tile's
    // sweeps in order until done or until a span would need more than K intervals; the array path
    // below goes on from that sweep and stamp (k0, st0), with the ray as the register path left it.
    uint k0 = 0u, st0 = 0u;
    if (!HAS_MESH && n <= K) {
        fn = n;
        if (n <= INLINE) {
            vec4 d = slab_inl[AX].v[ray];
            uint mm = slab_inl_mat[AX].v[ray];
            fe[0] = d.x; fx[0] = d.y; fm[0] = mm & 0xffffu;
            fe[1] = d.z; fx[1] = d.w; fm[1] = mm >> 16;
        } else {
            uint off = (m >> 11) * 8u;
            [[unroll]] for (uint i = 0u; i < K; ++i) {
                if (i < n) { vec2 p = slab_pool[AX].v[off + i]; fe[i] = p.x; fx[i] = p.y; fm[i] = slab_pool_mat[AX].v[off + i]; }
            }
        }
        bool full = false;
        for (; k0 < tile.w; ++k0) {
            GridSweep s = sweeps[sweep_index[tile.z + k0]];
            if (u < s.lo[ua] || u > s.hi[ua] || v < s.lo[va] || v > s.hi[va]) continue;
            uint op = s.code & 0xffu;
            uint mat = (s.code >> 16) & 0xffu;
            if (op == 0u) continue;
            for (st0 = 0u; st0 < s.stamps; ++st0) {
                float d0, d1;
                if (!sweep_chord(s, u, v, st0, d0, d1)) continue;
                if ((OPS & 2u) != 0u && op == 2u) { d0 = max(d0, 0.0); d1 = min(d1, DEPTH_CELLS); }
                uint r = fast_apply(op, d0, d1, mat);
                if (r == 2u) { full = true; break; }
                if (r == 1u) changed = true;
            }
            if (full) break;
        }
        n = fn;
        [[unroll]] for (uint i = 0u; i < K; ++i) { en[i] = fe[i]; ex[i] = fx[i]; mt[i] = fm[i]; }
        if (!full) { k0 = tile.w; st0 = 0u; }
    } else if (n <= INLINE) {
        vec4 d = slab_inl[AX].v[ray];
        uint mm = slab_inl_mat[AX].v[ray];
        en[0] = d.x; ex[0] = d.y; mt[0] = mm & 0xffffu;
        en[1] = d.z; ex[1] = d.w; mt[1] = mm >> 16;
    } else {
        uint off = (m >> 11) * 8u;
        for (uint i = 0u; i < n; ++i) {
            vec2 p = slab_pool[AX].v[off + i];
            en[i] = p.x; ex[i] = p.y; mt[i] = slab_pool_mat[AX].v[off + i];
        }
    }
    // The array path: every ray of a mesh-tool batch, rays over K intervals.
    for (uint k = k0; k < tile.w; ++k) {
        GridSweep s = sweeps[sweep_index[tile.z + k]];
        if (u < s.lo[ua] || u > s.hi[ua] || v < s.lo[va] || v > s.hi[va]) continue;
        uint op = s.code & 0xffu;
        uint mat = (s.code >> 16) & 0xffu;
        if (op == 0u) continue;
        // Every stamp gives spans: one analytic chord (ball, flat end) or the tool-ray intervals of a
        // kMesh sweep, in order; one apply_op call site keeps the kernel small for llvmpipe.
        bool mesh = HAS_MESH && ((s.code >> 8) & 0xffu) == 2u;
        MeshRay mr;
        if (mesh) mr = mesh_ray(s, u, v);
        for (uint st = k == k0 ? st0 : 0u; st < s.stamps; ++st) {
            float c0 = 0.0, c1 = 0.0, ca = 0.0;
            uint q = 0u, q1 = 1u;
            if (mesh) {
                if (!mesh_stamp(s, mr, st, q, q1, ca)) continue;
            } else if (!sweep_chord(s, u, v, st, c0, c1)) {
                continue;
            }
            for (; q < q1; ++q) {
                float d0 = c0, d1 = c1;
                if (mesh) {
                    precise float p0 = ca + uintBitsToFloat(tool_data[mr.dw + 2u * q]);
                    precise float p1 = ca + uintBitsToFloat(tool_data[mr.dw + 2u * q + 1u]);
                    precise float e0 = mr.base + p0;
                    precise float e1 = mr.base + p1;
                    d0 = e0;
                    d1 = e1;
                }
                uint r = apply_op(op, d0, d1, mat);
                if (r == 2u) { list_for_retry(ray); return; }
                if (r == 1u) changed = true;
            }
        }
    }
    // The ray's sweeps are complete only if no loop was cut short; then the write-back below must be too.
    if (loop_cap_spent()) { list_for_retry(ray | RETRY_LOOP_CAP); return; }
    if (!changed) return;
    uint cap = (m >> 7) & 15u;
    uint off_chunk = m >> 11;
    if (n <= INLINE) {
        vec4 d = vec4(0.0);
        uint mm = 0u;
        if (n > 0u) { d.x = en[0]; d.y = ex[0]; mm = mt[0]; }
        if (n > 1u) { d.z = en[1]; d.w = ex[1]; mm |= mt[1] << 16; }
        slab_inl[AX].v[ray] = d;
        slab_inl_mat[AX].v[ray] = mm;
    } else {
        if (cap * 8u < n) {  // a new pool region; the old one becomes garbage until the host compacts
            uint need = (n + 7u) / 8u;
            uint at = atomicAdd(counters[AX].pool_head, need);
            if (at + need > POOL_CHUNKS) { list_for_retry(ray); return; }
            cap = need;
            off_chunk = at;
        }
        uint off = off_chunk * 8u;
        for (uint i = 0u; i < n; ++i) {
            slab_pool[AX].v[off + i] = vec2(en[i], ex[i]);
            slab_pool_mat[AX].v[off + i] = mt[i];
        }
    }
    if (loop_cap_spent()) { list_for_retry(ray | RETRY_LOOP_CAP); return; }  // written in part: the host rewrites it
    slab_meta[AX].v[ray] = n | (cap << 7) | (off_chunk << 11);
    atomicAdd(counters[AX].changed_rays, 1u);
}

void main() {
    // Once the loop cap is spent this loop ends too: the tiles after the current one keep no done mark.
    for (uint t = gl_WorkGroupID.x; t < pc.tile_count; t += gl_NumWorkGroups.x) {
        sculpt_tile(t);
        if (gl_LocalInvocationID.x == 0u) tiles[pc.tile_count + t / 4u][t % 4u] = 1u;
    }
}
