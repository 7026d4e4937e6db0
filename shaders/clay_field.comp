// shaders/clay_field.comp - the clay tools' node field and its re-sampling into the three ray sets, on the GPU-resident
// model (compute/gpu/gpu_clay.cpp). One module, five kernels chosen by MODE (specialisation constant 0):
//   0 phi    one invocation per node of the field's box: phi from the three rays through the node
//            (compute/tools/clay_field.cpp clay_build_phi), NaN off the region, s0 = s1 = 0;
//   1 stamps one invocation per node: phi as mode 0, then a push's or pull's s0, s1 from the stamps
//            (compute/tools/clay_push.cpp clay_stamp_offsets), which read only the node's own phi;
//   2 smooth one invocation per node, one dispatch per act: the act's step of a smooth's s0, s1
//            (compute/tools/clay_smooth.cpp clay_smooth_offsets);
//   3 rays   one invocation per moved ray of one set (SET): the ray re-sampled at beta (compute/tools/clay_resample.cpp
//            clay_resample_ray), written to the output list; a ray needing more than plan.counts.z intervals is
//            marked for the host, which redoes it with the CPU reference;
//   4 grab   one invocation per node, after mode 0: a grab step's s0 (phi advected by the falloff of the motion,
//            reading phi trilinear around x - u) and s1 (compute/tools/clay_grab.cpp clay_grab_offsets).
// Every float operation is the CPU reference's, in its order, with contraction forbidden (precise), and std::min,
// std::max and std::clamp are spelt out with the same comparisons, so the results are bit for bit the CPU's (the
// C++ side is compiled with -ffp-contract=off).
#version 450
#extension GL_EXT_control_flow_attributes : require

layout(constant_id = 0) const uint MODE = 0u;
layout(local_size_x_id = 1) in;
// MODE 3: the ray set of this pipeline's jobs (one pipeline per set, so the slab bindings are chosen at compile time).
layout(constant_id = 2) const uint SET = 0u;

// The model's slabs (compute/gpu/gpu_dexel_slabs.hpp), five bindings per ray set a at 5a .. 5a + 4.
layout(std430, set = 0, binding = 0) readonly buffer Meta0 { uint meta0[]; };
layout(std430, set = 0, binding = 1) readonly buffer Inl0 { vec4 inl0[]; };
layout(std430, set = 0, binding = 2) readonly buffer InlMat0 { uint inl_mat0[]; };
layout(std430, set = 0, binding = 3) readonly buffer Pool0 { vec2 pool0[]; };
layout(std430, set = 0, binding = 4) readonly buffer PoolMat0 { uint pool_mat0[]; };
layout(std430, set = 0, binding = 5) readonly buffer Meta1 { uint meta1[]; };
layout(std430, set = 0, binding = 6) readonly buffer Inl1 { vec4 inl1[]; };
layout(std430, set = 0, binding = 7) readonly buffer InlMat1 { uint inl_mat1[]; };
layout(std430, set = 0, binding = 8) readonly buffer Pool1 { vec2 pool1[]; };
layout(std430, set = 0, binding = 9) readonly buffer PoolMat1 { uint pool_mat1[]; };
layout(std430, set = 0, binding = 10) readonly buffer Meta2 { uint meta2[]; };
layout(std430, set = 0, binding = 11) readonly buffer Inl2 { vec4 inl2[]; };
layout(std430, set = 0, binding = 12) readonly buffer InlMat2 { uint inl_mat2[]; };
layout(std430, set = 0, binding = 13) readonly buffer Pool2 { vec2 pool2[]; };
layout(std430, set = 0, binding = 14) readonly buffer PoolMat2 { uint pool_mat2[]; };
// The field at the box's nodes (ClayBox::index order): phi as float bits (NaN off the region), s0, s1. s0 has two
// halves of plan.counts.x floats: a smooth's acts step from one into the other, the last act into the first (the
// one the host reads and MODE 3 re-samples).
layout(std430, set = 0, binding = 15) buffer Phi { uint phi_bits[]; };
layout(std430, set = 0, binding = 16) buffer S0 { float s0v[]; };
layout(std430, set = 0, binding = 17) buffer S1 { float s1v[]; };
// The operation (compute/gpu/gpu_clay.cpp GpuClay::Header) in a uniform buffer: llvmpipe loads uniform words once
// for all lanes, storage words lane by lane with a bounds check each.
layout(std140, set = 0, binding = 18) uniform Plan {
    ivec4 box_lo;
    ivec4 box_hi;
    ivec4 box_n;       // nodes per axis
    ivec4 move_lo;     // clay_movable_range per axis
    ivec4 move_hi;
    ivec4 ray_nu;      // RaySet::nu of sets 0, 1, 2
    uvec4 chord_at;    // xyz: first word of each set's chords in chord_words[]; w: first word of the stamps
    uvec4 counts;      // x: nodes of the box; y: stamps (smooth: acts); z: most intervals a re-sampled ray may have here;
                       // w: ClayStampParams::rim_cap (float bits)
    vec4 consts;       // x: search (phi's clamp); y: phi's floor 1e-6; z: kClaySmoothRate; w: kClayMaxBeta
    vec4 stamp_par;    // ClayStampParams r, w, reach2, sign; grab: ClayGrabParams r, core
} plan;
// Per set a the region chords (lo, hi) of the box's rays (ClayField::chords order) from word plan.chord_at[a]; then
// the stamps, 8 words each (p, delta, n, 0; float bits), or a smooth's acts, 8 words each (contact point, r, outward
// normal, 0; float bits), or a grab's anchor and motion (anchor, 0, v, 0; float bits), from word plan.chord_at.w.
layout(std430, set = 0, binding = 21) readonly buffer Chords { uint chord_words[]; };
// Moved rays to re-sample: per job 8 words (set, u, v, lo, hi, varies, first output word, unused).
layout(std430, set = 0, binding = 19) readonly buffer Jobs { uint jobs[]; };
// Per job from its first word: the interval count (0xffffffff: more than plan.counts.z, redo on the host), then
// 3 words per interval: enter bits, exit bits, enter material | exit material << 8.
layout(std430, set = 0, binding = 20) writeonly buffer Out { uint outw[]; };

layout(push_constant) uniform Push {
    uint first;   // first node (modes 0-2) or job (mode 3) of this dispatch
    uint count;   // nodes or jobs in this dispatch
    float beta;   // mode 3: the s1 weight for rays with varies set
    uint act;     // mode 2: the act of this dispatch
} pc;

// std::min(a, b), std::max(a, b), std::clamp(x, lo, hi) with their comparisons.
float cmin(float a, float b) { return b < a ? b : a; }
float cmax(float a, float b) { return a < b ? b : a; }
float cclamp(float x, float lo, float hi) { return x < lo ? lo : (hi < x ? hi : x); }

// ---- rays of the slabs ----
uint ray_meta(uint a, uint ray) {
    if (a == 0u) return meta0[ray];
    if (a == 1u) return meta1[ray];
    return meta2[ray];
}
// End e (enter of interval e/2 when e is even, else its exit) of ray `ray` of set a with meta word m.
float ray_end(uint a, uint ray, uint m, uint e) {
    const uint iv = e >> 1;
    const bool ex = (e & 1u) != 0u;
    if ((m & 127u) <= 2u) {
        vec4 d = a == 0u ? inl0[ray] : (a == 1u ? inl1[ray] : inl2[ray]);
        return iv == 0u ? (ex ? d.y : d.x) : (ex ? d.w : d.z);
    }
    const uint at = (m >> 11) * 8u + iv;
    vec2 d = a == 0u ? pool0[at] : (a == 1u ? pool1[at] : pool2[at]);
    return ex ? d.y : d.x;
}
uint ray_mat(uint a, uint ray, uint m, uint e) {
    const uint iv = e >> 1;
    uint pair;
    if ((m & 127u) <= 2u) {
        const uint mm = a == 0u ? inl_mat0[ray] : (a == 1u ? inl_mat1[ray] : inl_mat2[ray]);
        pair = iv == 0u ? (mm & 0xffffu) : (mm >> 16);
    } else {
        const uint at = (m >> 11) * 8u + iv;
        pair = a == 0u ? pool_mat0[at] : (a == 1u ? pool_mat1[at] : pool_mat2[at]);
    }
    return (e & 1u) != 0u ? ((pair >> 8) & 0xffu) : (pair & 0xffu);
}

// ---- the box ----
uint box_index(ivec3 nd) {
    return uint(nd.x - plan.box_lo.x) + uint(plan.box_n.x) * (uint(nd.y - plan.box_lo.y) + uint(plan.box_n.y) * uint(nd.z - plan.box_lo.z));
}
ivec3 box_node(uint x) {
    const uint nx = uint(plan.box_n.x), ny = uint(plan.box_n.y);
    return plan.box_lo.xyz + ivec3(int(x % nx), int((x / nx) % ny), int(x / (nx * ny)));
}
// The region chord [lo, hi] (lo > hi: none) of the ray of set a through box nodes (u, v).
ivec2 chord(uint a, int u, int v) {
    const uint ua = (a + 1u) % 3u, va = (a + 2u) % 3u;
    const uint at = plan.chord_at[a] + 2u * (uint(u - plan.box_lo[ua]) + uint(plan.box_n[ua]) * uint(v - plan.box_lo[va]));
    return ivec2(int(chord_words[at]), int(chord_words[at + 1u]));
}
float phi_at(uint x) { return uintBitsToFloat(phi_bits[x]); }

// ---- mode 0: phi (clay_build_phi) ----
void build_phi(uint x, ivec3 nd) {
    s0v[x] = 0.0;
    s0v[plan.counts.x + x] = 0.0;
    s1v[x] = 0.0;
    const ivec2 run0 = chord(0u, nd.y, nd.z);
    if (nd.x < run0.x || nd.x > run0.y) {
        phi_bits[x] = 0xffffffffu;  // off the region: the CPU's NaN, bit for bit
        return;
    }
    const float K = plan.consts.x;
    uint votes = 0u;
    bool touching = false;
    precise float inv = 0.0;
    [[unroll]] for (uint a = 0u; a < 3u; ++a) {
        const uint ua = (a + 1u) % 3u, va = (a + 2u) % 3u;
        const ivec2 run = chord(a, nd[ua], nd[va]);
        if (nd[a] < run.x || nd[a] > run.y) continue;
        const uint ray = uint(nd[ua]) + uint(plan.ray_nu[a]) * uint(nd[va]);
        const uint m = ray_meta(a, ray);
        const uint ne = 2u * (m & 127u);
        const float depth = float(nd[a]);
        uint q = 0u;  // first end >= depth
        while (q < ne && ray_end(a, ray, m, q) < depth) ++q;
        float dist = K;
        if (q > 0u) {
            precise float e = abs(ray_end(a, ray, m, q - 1u) - depth);
            dist = cmin(dist, e);
        }
        if (q < ne) {
            precise float e = abs(ray_end(a, ray, m, q) - depth);
            dist = cmin(dist, e);
        }
        votes += q & 1u;
        if (dist == 0.0) {
            touching = true;
        } else if (dist < K) {
            precise float t = 1.0 / (dist * dist);
            inv = inv + t;
        }
    }
    float mag = K;
    if (touching) {
        mag = 0.0;
    } else if (inv > 0.0) {
        precise float m = 1.0 / sqrt(inv);
        mag = cmin(mag, m);
    }
    mag = cmax(mag, plan.consts.y);
    phi_bits[x] = floatBitsToUint(votes >= 2u ? -mag : mag);
}

// True when node nd lies in the region (set 0's chord) and clay_node_fixed lets it move.
bool movable(ivec3 nd) {
    if (any(lessThan(nd, plan.move_lo.xyz)) || any(greaterThan(nd, plan.move_hi.xyz))) return false;
    const ivec2 run0 = chord(0u, nd.y, nd.z);
    return nd.x >= run0.x && nd.x <= run0.y;
}

// ---- mode 1: a push's or pull's s0, s1 (clay_stamp_offsets) ----

void stamp_offsets(uint x, ivec3 nd) {
    if (!movable(nd)) return;
    const float phi = phi_at(x);
    const vec3 q = vec3(nd);
    const float r = plan.stamp_par.x, w = plan.stamp_par.y, reach2 = plan.stamp_par.z, sgn = plan.stamp_par.w;
    const float rim_cap = uintBitsToFloat(plan.counts.w);
    const uint stamps = plan.counts.y, first = plan.chord_at.w;
    float dent = 0.0, rim = 0.0;
    for (uint s = 0u; s < stamps; ++s) {
        const uint at = first + 8u * s;
        const vec4 sp = uintBitsToFloat(uvec4(chord_words[at], chord_words[at + 1u], chord_words[at + 2u], chord_words[at + 3u]));
        const vec4 sn = uintBitsToFloat(uvec4(chord_words[at + 4u], chord_words[at + 5u], chord_words[at + 6u], 0u));
        precise float dx = q.x - sp.x;
        precise float dy = q.y - sp.y;
        precise float dz = q.z - sp.z;
        precise float d2 = dx * dx + dy * dy + dz * dz;
        if (d2 > reach2) continue;
        precise float d = sqrt(d2);
        precise float depth = -(dx * sn.x + dy * sn.y + dz * sn.z);
        const float delta = sp.w;
        precise float sheet = delta + 2.0 + 0.5 * d;
        if (depth > sheet) continue;
        precise float rw = r + w;
        if (d < r) {
            precise float xr = d / r;
            precise float k = delta * (1.0 - xr * xr);
            dent = cmax(dent, k);
        } else if (d < rw) {
            precise float xr = (d - r) / w;
            precise float b = 4.0 * xr * (1.0 - xr);
            precise float k = cmin(delta, rim_cap) * (b * b);
            rim = cmax(rim, k);
        }
    }
    if (dent > 0.0) {
        precise float lim = dent + 2.0;
        if (abs(phi) < lim) {
            precise float s = sgn * dent;
            s0v[x] = s;
        }
    } else if (rim > 0.0) {
        precise float lim = rim * plan.consts.w + 2.0;
        if (abs(phi) < lim) {
            precise float s = -sgn * rim;
            s1v[x] = s;
        }
    }
}

// ---- mode 2: one act's step of a smooth's s0, s1 (clay_smooth_offsets) ----
// Act k of K reads s0 from half (K - k) & 1 and writes half (K - k - 1) & 1 at every node (its old value where the act
// does not move it), so the last act writes half 0; MODE 0 zeroes both.
void smooth_offsets(uint x, ivec3 nd) {
    const uint n = plan.counts.x, acts = plan.counts.y;
    const uint src = ((acts - pc.act) & 1u) * n, dst = ((acts - pc.act - 1u) & 1u) * n;
    const float old = s0v[src + x];
    s0v[dst + x] = old;
    if (!movable(nd)) return;
    const float phi = phi_at(x);
    if (!(abs(phi) < 2.0)) return;
    const uint at = plan.chord_at.w + 8u * pc.act;
    const vec3 point = vec3(uintBitsToFloat(chord_words[at]), uintBitsToFloat(chord_words[at + 1u]),
                            uintBitsToFloat(chord_words[at + 2u]));
    const float r = uintBitsToFloat(chord_words[at + 3u]);
    const vec3 normal = vec3(uintBitsToFloat(chord_words[at + 4u]), uintBitsToFloat(chord_words[at + 5u]),
                             uintBitsToFloat(chord_words[at + 6u]));
    precise float dx = float(nd.x) - point.x;
    precise float dy = float(nd.y) - point.y;
    precise float dz = float(nd.z) - point.z;
    precise float d = sqrt(dx * dx + dy * dy + dz * dz);
    if (!(d < r)) return;
    precise float depth = -(dx * normal.x + dy * normal.y + dz * normal.z);
    precise float sheet = 0.0 + 2.0 + 0.5 * d;
    if (depth > sheet) return;
    precise float xr = d / r;
    precise float wgt = 1.0 - xr * xr;
    const uint sy = uint(plan.box_n.x), sz = uint(plan.box_n.x) * uint(plan.box_n.y);
    precise float pxm = phi_at(x - 1u) + s0v[src + x - 1u];
    precise float pxp = phi_at(x + 1u) + s0v[src + x + 1u];
    precise float pym = phi_at(x - sy) + s0v[src + x - sy];
    precise float pyp = phi_at(x + sy) + s0v[src + x + sy];
    precise float pzm = phi_at(x - sz) + s0v[src + x - sz];
    precise float pzp = phi_at(x + sz) + s0v[src + x + sz];
    precise float pc0 = phi + old;
    precise float lap = pxm + pxp + pym + pyp + pzm + pzp - 6.0 * pc0;
    precise float s = plan.consts.z * wgt * lap;
    precise float nw = old + s;
    s0v[dst + x] = nw;
    s1v[x] = cmax(s1v[x], wgt);
}

// ---- mode 4: a grab step's s0 (clay_grab_offsets) ----
// phi trilinear at grid point p from the box's nodes, p clamped into the box (clay_phi_at).
float phi_trilinear(vec3 p) {
    ivec3 i0;
    vec3 w;
    [[unroll]] for (int a = 0; a < 3; ++a) {
        const float lo = float(plan.box_lo[a]), hi = float(plan.box_hi[a]);
        const float c = cclamp(p[a], lo, hi);
        float fl = floor(c);
        if (fl >= hi) fl = hi - 1.0;
        if (fl < lo) fl = lo;
        i0[a] = int(fl);
        precise float wa = c - fl;
        w[a] = wa;
    }
    const ivec3 i1 = min(i0 + ivec3(1), plan.box_hi.xyz);
    const float p000 = phi_at(box_index(ivec3(i0.x, i0.y, i0.z))), p100 = phi_at(box_index(ivec3(i1.x, i0.y, i0.z)));
    const float p010 = phi_at(box_index(ivec3(i0.x, i1.y, i0.z))), p110 = phi_at(box_index(ivec3(i1.x, i1.y, i0.z)));
    const float p001 = phi_at(box_index(ivec3(i0.x, i0.y, i1.z))), p101 = phi_at(box_index(ivec3(i1.x, i0.y, i1.z)));
    const float p011 = phi_at(box_index(ivec3(i0.x, i1.y, i1.z))), p111 = phi_at(box_index(ivec3(i1.x, i1.y, i1.z)));
    precise float c00 = p000 + w.x * (p100 - p000);
    precise float c10 = p010 + w.x * (p110 - p010);
    precise float c01 = p001 + w.x * (p101 - p001);
    precise float c11 = p011 + w.x * (p111 - p011);
    precise float c0 = c00 + w.y * (c10 - c00);
    precise float c1 = c01 + w.y * (c11 - c01);
    precise float v = c0 + w.z * (c1 - c0);
    return v;
}

void grab_offsets(uint x, ivec3 nd) {
    if (!movable(nd)) return;
    const uint at = plan.chord_at.w;
    const vec3 anchor = vec3(uintBitsToFloat(chord_words[at]), uintBitsToFloat(chord_words[at + 1u]),
                             uintBitsToFloat(chord_words[at + 2u]));
    const vec3 v = vec3(uintBitsToFloat(chord_words[at + 4u]), uintBitsToFloat(chord_words[at + 5u]),
                        uintBitsToFloat(chord_words[at + 6u]));
    const float r = plan.stamp_par.x, core = plan.stamp_par.y;
    precise float r2 = r * r;
    precise float dx = float(nd.x) - anchor.x;
    precise float dy = float(nd.y) - anchor.y;
    precise float dz = float(nd.z) - anchor.z;
    precise float d2 = dx * dx + dy * dy + dz * dz;
    if (!(d2 < r2)) return;
    precise float d = sqrt(d2);
    precise float w = 1.0;  // clay_grab_falloff
    if (d > core) {
        precise float t = (d - core) / (r - core);
        precise float q = 1.0 - t * t;
        w = d < r ? q * q : 0.0;
    }
    precise float qx = float(nd.x) - w * v.x;
    precise float qy = float(nd.y) - w * v.y;
    precise float qz = float(nd.z) - w * v.z;
    const float phi = phi_at(x);
    precise float s = phi_trilinear(vec3(qx, qy, qz)) - phi;
    s0v[x] = s;
    precise float psi = phi + s;
    precise float band = plan.consts.w + 1.0;
    if (abs(psi) < band) s1v[x] = w;
}

// ---- mode 3: one moved ray re-sampled (clay_resample_ray) ----
uint out_at, out_n;
bool overflow;
bool has_last;    // the last output interval, kept until the next one starts (a touching one merges into it)
float last_en, last_ex;
uint last_me, last_mx;
bool has_enter;   // a crossing waiting for its pair
float enter_t;
uint enter_m;

void flush_last() {
    if (!has_last) return;
    if (out_n >= plan.counts.z) {
        overflow = true;
        return;
    }
    const uint at = out_at + 1u + 3u * out_n;
    outw[at] = floatBitsToUint(last_en);
    outw[at + 1u] = floatBitsToUint(last_ex);
    outw[at + 2u] = last_me | (last_mx << 8);
    ++out_n;
}

// The crossings in order, paired (0, 1), (2, 3), ... into sorted, non-touching intervals; empty ones vanish.
void emit(float t, uint m) {
    if (!has_enter) {
        has_enter = true;
        enter_t = t;
        enter_m = m;
        return;
    }
    has_enter = false;
    if (!(enter_t < t)) return;
    if (has_last && !(last_ex < enter_t)) {  // touches the previous one: merge
        last_ex = cmax(last_ex, t);
        last_mx = m;
        return;
    }
    flush_last();
    has_last = true;
    last_en = enter_t;
    last_ex = t;
    last_me = enter_m;
    last_mx = m;
}

// Material of the ray's old end nearest to depth t (0 when the ray had none).
uint nearest_material(uint a, uint ray, uint m, float t) {
    uint mat = 0u;
    float best = 3.4e38;
    const uint ne = 2u * (m & 127u);
    for (uint e = 0u; e < ne; ++e) {
        precise float d = abs(ray_end(a, ray, m, e) - t);
        if (d < best) {
            best = d;
            mat = ray_mat(a, ray, m, e);
        }
    }
    return mat;
}

void resample(uint job) {
    const uint j = 8u * job;
    const uint a = SET;  // jobs[j] holds it too
    const int u = int(jobs[j + 1u]), v = int(jobs[j + 2u]), lo = int(jobs[j + 3u]), hi = int(jobs[j + 4u]);
    const float beta = jobs[j + 5u] != 0u ? pc.beta : 0.0;
    out_at = jobs[j + 6u];
    out_n = 0u;
    overflow = false;
    has_last = false;
    has_enter = false;
    ivec3 nd;
    nd[(a + 1u) % 3u] = u;
    nd[(a + 2u) % 3u] = v;
    nd[a] = lo;
    const uint base = box_index(nd);
    const uint stride = a == 0u ? 1u : (a == 1u ? uint(plan.box_n.x) : uint(plan.box_n.x) * uint(plan.box_n.y));
    const uint ray = uint(u) + uint(plan.ray_nu[a]) * uint(v);
    const uint m = ray_meta(a, ray);
    const uint ne = 2u * (m & 127u);
    uint q = 0u;  // next old crossing
    const float flo = float(lo);
    while (q < ne && ray_end(a, ray, m, q) < flo) {
        emit(ray_end(a, ray, m, q), ray_mat(a, ray, m, q));
        ++q;
    }
    bool status = (q & 1u) != 0u;  // the ray's status just below node lo
    for (int d = lo; d < hi; ++d) {
        const uint i0 = base + uint(d - lo) * stride, i1 = i0 + stride;
        precise float s0 = s0v[i0] + beta * s1v[i0];
        precise float s1 = s0v[i1] + beta * s1v[i1];
        const float fd1 = float(d + 1);
        if (s0 == 0.0 && s1 == 0.0) {  // the edge keeps its old crossings
            while (q < ne && ray_end(a, ray, m, q) < fd1) {
                emit(ray_end(a, ray, m, q), ray_mat(a, ray, m, q));
                ++q;
            }
            status = (q & 1u) != 0u;
            continue;
        }
        precise float p0 = phi_at(i0) + s0;
        precise float p1 = phi_at(i1) + s1;
        const bool st0 = s0 != 0.0 ? p0 < 0.0 : status;
        uint q1 = q;
        while (q1 < ne && ray_end(a, ray, m, q1) < fd1) ++q1;
        const bool st1 = s1 != 0.0 ? p1 < 0.0 : (q1 & 1u) != 0u;
        q = q1;
        if (st0 != st1) {
            float t;
            if ((p0 < 0.0) != (p1 < 0.0)) {
                precise float w = p0 / (p0 - p1);
                precise float tt = float(d) + cclamp(w, 0.0, 1.0);
                t = tt;
            } else {
                precise float tt = float(d) + 0.5;  // the old ray disagreed with the field at its unmoved end
                t = tt;
            }
            emit(t, nearest_material(a, ray, m, t));
        }
        status = st1;
    }
    while (q < ne) {
        emit(ray_end(a, ray, m, q), ray_mat(a, ray, m, q));
        ++q;
    }
    flush_last();
    outw[out_at] = overflow ? 0xffffffffu : out_n;
}

void main() {
    if (gl_GlobalInvocationID.x >= pc.count) return;
    const uint g = pc.first + gl_GlobalInvocationID.x;
    if (MODE == 3u) {
        resample(g);
        return;
    }
    const ivec3 nd = box_node(g);
    if (MODE == 0u) {
        build_phi(g, nd);
    } else if (MODE == 1u) {  // a node's stamp offsets read only its own phi: one kernel does both
        build_phi(g, nd);
        stamp_offsets(g, nd);
    } else if (MODE == 2u) {
        smooth_offsets(g, nd);
    } else {
        grab_offsets(g, nd);
    }
}
