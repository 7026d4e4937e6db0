// shaders/dexel_contour_vertices.glsl - part of dexel_contour.comp: the dual vertices of one cell (one per
// surface component, at the mean of its crossings, clamped into the cell; nearest-crossing material).

// The vertices of used cell `cell` (TileContourer::cell_vertices) into slots base .. base + components - 1.
// Loops over the 12 edges and 4 components are unrolled so the per-edge arrays stay in registers; the
// sums run in the CPU's order (ascending edge per component), so the doubles are the same.
void place_vertices(ivec3 cell, uint base) {
    int cfg = config(cell);
    int comps = components(cfg);
    double tq[12];
    uint mq[12];
    int cq[12];
    [[unroll]] for (int e = 0; e < 12; ++e) {
        cq[e] = edge_component(cfg, e);
        tq[e] = 0.0lf;
        mq[e] = 0u;
        if (cq[e] < 0) continue;
        const int a = e / 4;
        ivec3 off = ivec3(0);
        off[(a + 1) % 3] = e & 1;
        off[(a + 2) % 3] = (e >> 1) & 1;
        const int corner = off.x + 2 * off.y + 4 * off.z;
        uint m;
        tq[e] = edge_crossing(a, cell + off, ((cfg >> corner) & 1) != 0, m);
        mq[e] = m;
    }
    dvec3 clo = dvec3(cell);
    uint voff = region[job_tile[pc.job_base + gl_WorkGroupID.x]].x;
    [[unroll]] for (int c = 0; c < 4; ++c) {
        if (c >= comps) break;
        dvec3 sum = dvec3(0.0lf);
        int count = 0;
        [[unroll]] for (int e = 0; e < 12; ++e) {
            if (cq[e] != c) continue;
            const int a = e / 4;
            dvec3 q = clo;
            q[(a + 1) % 3] += double(e & 1);
            q[(a + 2) % 3] += double((e >> 1) & 1);
            q[a] = tq[e];
            precise dvec3 s = sum + q;
            sum = s;
            ++count;
        }
        precise dvec3 mean = sum / double(count);
        dvec3 pos = min(max(mean, clo), clo + dvec3(1.0lf));
        double best_d2 = -1.0lf;
        uint best_mat = 0u;
        [[unroll]] for (int e = 0; e < 12; ++e) {
            if (cq[e] != c) continue;
            const int a = e / 4;
            dvec3 q = clo;
            q[(a + 1) % 3] += double(e & 1);
            q[(a + 2) % 3] += double((e >> 1) & 1);
            q[a] = tq[e];
            precise dvec3 d = q - pos;
            double d2 = dot3(d);
            if (best_d2 < 0.0lf || d2 < best_d2 || (d2 == best_d2 && mq[e] > best_mat)) {
                best_d2 = d2;
                best_mat = mq[e];
            }
        }
        uint v = voff + base + uint(c);
        vtx[v].grid = vec3(pos);
        vtx[v].material = best_mat;
        vd[3u * v] = pos.x;
        vd[3u * v + 1u] = pos.y;
        vd[3u * v + 2u] = pos.z;
    }
}

