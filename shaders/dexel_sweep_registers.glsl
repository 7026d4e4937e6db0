// shaders/dexel_sweep_registers.glsl - included by dexel_sweep.comp: its register path, the same interval
// operations for rays of at most K intervals with constant indices only.
// ---- the register path: rays of at most K intervals ----
// llvmpipe turns dynamically indexed private arrays into per-lane gathers and scatters; here every index
// is a constant (unrolled loops, selects), so fe/fx/fm live in registers. Same comparisons and moves as
// subtract_span / union_span / paint_span above, in one body: a span replaces intervals [first, last) by
// `pieces` new ones (subtract: the kept head and tail; union: the merged or inserted interval).
float fe[K];
float fx[K];
uint fm[K];
uint fn;

// Applies one span with op 1 (subtract), 2 (union, span already clipped) or 3 (paint); 0 = unchanged,
// 1 = changed, 2 = the result needs more than K intervals (ray left as it was).
uint fast_apply(uint op, float t0, float t1, uint mat) {
    bool sub = OPS == 1u || ((OPS & 1u) != 0u && op == 1u);
    bool pnt = OPS == 4u || ((OPS & 4u) != 0u && op == 3u);
    if (pnt ? !(t0 <= t1) : !(t0 < t1)) return 0u;
    // subtract: first = intervals with exit <= t0, last = those with enter < t1;
    // union, paint: first = intervals with exit < t0, last = those with enter <= t1.
    uint first = 0u, lastc = 0u;
    [[unroll]] for (uint i = 0u; i < K; ++i) {
        bool a = sub ? !(t0 < fx[i]) : fx[i] < t0;
        bool b = sub ? fe[i] < t1 : !(t1 < fe[i]);
        if (i < fn && a) ++first;
        if (i < fn && b) ++lastc;
    }
    uint last = max(first, lastc);
    if ((OPS & 4u) != 0u && pnt) {
        bool changed = false;
        [[unroll]] for (uint i = 0u; i < K; ++i) {
            uint m = fm[i];
            if (i >= first && i < last) {
                if (t0 <= fe[i] && (m & 0xffu) != mat) m = (m & 0xff00u) | mat;
                if (fx[i] <= t1 && ((m >> 8) & 0xffu) != mat) m = (m & 0xffu) | (mat << 8);
            }
            changed = changed || m != fm[i];
            fm[i] = m;
        }
        return changed ? 1u : 0u;
    }
    if (sub && first == last) return 0u;
    float h_en = 0.0, h_ex = 0.0, t_ex = 0.0;
    uint h_m = 0u, t_m = 0u;
    [[unroll]] for (uint i = 0u; i < K; ++i) {
        if (i == first) { h_en = fe[i]; h_ex = fx[i]; h_m = fm[i]; }
        if (i + 1u == last) { t_ex = fx[i]; t_m = fm[i]; }
    }
    float p0e, p0x, p1e = t1, p1x = t_ex;
    uint p0m, p1m = mat | (t_m & 0xff00u), pieces;
    if (sub) {
        bool keep_head = h_en < t0, keep_tail = t1 < t_ex;
        pieces = (keep_head ? 1u : 0u) + (keep_tail ? 1u : 0u);
        p0e = keep_head ? h_en : t1;
        p0x = keep_head ? t0 : t_ex;
        p0m = keep_head ? (h_m & 0xffu) | (mat << 8) : p1m;
    } else if ((OPS & 2u) == 0u) {
        return 0u;  // not reached: with neither subtract nor union only paint spans come here
    } else if (first == last) {
        pieces = 1u;
        p0e = t0; p0x = t1; p0m = mat | (mat << 8);
    } else {
        if (last == first + 1u && h_en <= t0 && t1 <= h_ex) return 0u;
        pieces = 1u;
        p0e = h_en; p0x = t_ex; p0m = (h_m & 0xffu) | (t_m & 0xff00u);
        if (t0 < p0e) { p0e = t0; p0m = (p0m & 0xff00u) | mat; }
        if (t1 > p0x) { p0x = t1; p0m = (p0m & 0xffu) | (mat << 8); }
    }
    uint nn = fn - (last - first) + pieces;
    if (nn > K) return 2u;
    uint skip = last - first;  // slot j >= first + pieces takes old slot j - pieces + skip
    float ne[K], nx[K];
    uint nm[K];
    [[unroll]] for (uint j = 0u; j < K; ++j) {
        float e = fe[j], x = fx[j];
        uint m = fm[j];
        if (j >= first) {
            if (j < first + pieces) {
                bool p0 = j == first;
                e = p0 ? p0e : p1e; x = p0 ? p0x : p1x; m = p0 ? p0m : p1m;
            } else {
                uint src = j + skip - pieces;
                [[unroll]] for (uint i = 0u; i < K; ++i)
                    if (i == src) { e = fe[i]; x = fx[i]; m = fm[i]; }
            }
        }
        ne[j] = e; nx[j] = x; nm[j] = m;
    }
    [[unroll]] for (uint j = 0u; j < K; ++j) { fe[j] = ne[j]; fx[j] = nx[j]; fm[j] = nm[j]; }
    fn = nn;
    return 1u;
}
