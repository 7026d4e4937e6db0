// shaders/dexel_sweep_spans.glsl - included by dexel_sweep.comp: its array path's interval operations on
// the ray held in the private arrays en/ex/mt (n intervals), step for step as compute/model/interval_ops.cpp.
// ---- interval operations (compute/model/interval_ops.cpp) ----
// Moves intervals [from, n) by `by` places (by may be negative) and sets n += by.
void shift_tail(uint from, int by) {
    if (by > 0) {
        for (int i = int(n) - 1; i >= int(from); --i) {
            en[i + by] = en[i]; ex[i + by] = ex[i]; mt[i + by] = mt[i];
        }
    } else if (by < 0) {
        for (uint i = from; i < n; ++i) {
            en[int(i) + by] = en[i]; ex[int(i) + by] = ex[i]; mt[int(i) + by] = mt[i];
        }
    }
    n = uint(int(n) + by);
}

// Applies one span with the sweep's op; 0 = unchanged, 1 = changed, 2 = would exceed MAXI.
uint subtract_span(float t0, float t1, uint cut);
uint union_span(float t0, float t1, uint mat);
uint paint_span(float t0, float t1, uint mat);
uint apply_op(uint op, float d0, float d1, uint mat) {
    if ((OPS & 1u) != 0u && op == 1u) return subtract_span(d0, d1, mat);
    if ((OPS & 2u) != 0u && op == 2u) return union_span(max(d0, 0.0), min(d1, DEPTH_CELLS), mat);
    if ((OPS & 4u) != 0u && op == 3u) return paint_span(d0, d1, mat);
    return 0u;
}

// Returns 0 = unchanged, 1 = changed, 2 = would exceed MAXI (ray left as it was).
uint subtract_span(float t0, float t1, uint cut) {
    if (!(t0 < t1)) return 0u;
    uint first = 0u;
    while (first < n && !(t0 < ex[first])) ++first;
    uint last = first;
    while (last < n && en[last] < t1) ++last;
    if (first == last) return 0u;
    float head_enter = en[first];
    uint head_mat = (mt[first] & 0xffu) | (cut << 8);
    float tail_exit = ex[last - 1u];
    uint tail_mat = cut | (mt[last - 1u] & 0xff00u);
    bool keep_head = head_enter < t0, keep_tail = t1 < tail_exit;
    int pieces = (keep_head ? 1 : 0) + (keep_tail ? 1 : 0);
    int by = pieces - int(last - first);
    if (int(n) + by > int(MAXI)) return 2u;
    shift_tail(last, by);
    uint at = first;
    if (keep_head) { en[at] = head_enter; ex[at] = t0; mt[at] = head_mat; ++at; }
    if (keep_tail) { en[at] = t1; ex[at] = tail_exit; mt[at] = tail_mat; }
    return 1u;
}

uint union_span(float t0, float t1, uint mat) {
    if (!(t0 < t1)) return 0u;
    uint first = 0u;
    while (first < n && ex[first] < t0) ++first;
    uint last = first;
    while (last < n && !(t1 < en[last])) ++last;
    if (first == last) {
        if (n + 1u > MAXI) return 2u;
        shift_tail(first, 1);
        en[first] = t0; ex[first] = t1; mt[first] = mat | (mat << 8);
        return 1u;
    }
    if (last == first + 1u && en[first] <= t0 && t1 <= ex[first]) return 0u;
    float m_en = en[first], m_ex = ex[last - 1u];
    uint m_enm = mt[first] & 0xffu, m_exm = mt[last - 1u] & 0xff00u;
    if (t0 < m_en) { m_en = t0; m_enm = mat; }
    if (t1 > m_ex) { m_ex = t1; m_exm = mat << 8; }
    shift_tail(last, 1 - int(last - first));
    en[first] = m_en; ex[first] = m_ex; mt[first] = m_enm | m_exm;
    return 1u;
}

uint paint_span(float t0, float t1, uint mat) {
    if (!(t0 <= t1)) return 0u;
    uint changed = 0u;
    uint i = 0u;
    while (i < n && ex[i] < t0) ++i;
    for (; i < n && en[i] <= t1; ++i) {
        if (t0 <= en[i] && (mt[i] & 0xffu) != mat) { mt[i] = (mt[i] & 0xff00u) | mat; changed = 1u; }
        if (ex[i] <= t1 && ((mt[i] >> 8) & 0xffu) != mat) { mt[i] = (mt[i] & 0xffu) | (mat << 8); changed = 1u; }
    }
    return changed;
}
