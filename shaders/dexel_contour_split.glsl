// shaders/dexel_contour_split.glsl - part of dexel_contour.comp: the face-split rule of the CPU
// contourer (compute/contour/contour_tile.hpp) for tunnels thinner than a cell: split-face vertices and the fans
// around the crossing points of edges next to split faces. Uses the including shader's shared lists.

// The face around edge (n, a) between ring cells r and r + 1 (TileContourer::emit_edge): lower cell, axis.
void ring_face(ivec3 n, int a, int r, out ivec3 lower, out int g) {
    const int fr[4] = int[4](0, 1, 3, 0);
    lower = ring_cell(n, a, fr[r]);
    g = (r & 1) == 0 ? (a + 1) % 3 : (a + 2) % 3;
}

// Index of split face (lower, g) in the face list, or NONE16 when it is not split.
uint face_index_of(ivec3 lower, int g) {
    uint key = cache_index(lower) | (uint(g) << 13);
    uint nfaces = min(s_faces, FACE_CAP);
    for (uint i = 0u; i < nfaces; ++i)
        if (face_list[i] == key) return i;
    return NONE16;
}

// The segment vertices of split face i (TileContourer::emit_split_face): for each inside corner p of the
// face, the QEF of the crossings on the face's two edges at p that have a normal (components across the
// face zeroed), minimised over the face square and clamped into the rectangle spanned by p and the two
// crossings; the crossings' mean when neither has a normal (material: the nearer crossing, ties to the
// larger id); of two nearly opposite normals (a sheet's facing walls) only the first. Outside corners' slots get
// the face centre (never referenced).
void place_face_vertices(uint i, uint v0) {
    uint key = face_list[i];
    uint ci = key & 8191u;
    int f = int(key >> 13), f1 = (f + 1) % 3, f2 = (f + 2) % 3;
    ivec3 fmin = lo + ivec3(int(ci) % CS, (int(ci) / CS) % CS, int(ci) / (CS * CS)) + unit(f);
    for (int idx = 0; idx < 4; ++idx) {
        ivec3 p = fmin + (idx & 1) * unit(f1) + ((idx >> 1) & 1) * unit(f2);
        dvec3 pos = dvec3(fmin);
        pos[f1] += 0.5lf;
        pos[f2] += 0.5lf;
        uint mat = 0u;
        if (inside(p)) {
            dvec3 pts[2];
            uint mats[2];
            bool has_n[2];
            for (int m = 0; m < 2; ++m) {
                int g = m == 0 ? f1 : f2;
                int off = m == 0 ? (idx & 1) : ((idx >> 1) & 1);
                ivec3 s = p - off * unit(g);
                uint em;
                bool fb, ex;
                bool s_in = inside(s);
                double t = edge_crossing(g, s, s_in, em, fb, ex);
                pts[m] = dvec3(s);
                pts[m][g] = t;
                mats[m] = em;
                has_n[m] = !fb && ex == s_in;  // a normal is estimated only for these (as in place_vertices)
            }
            precise dvec3 sum = (dvec3(0.0lf) + pts[0]) + pts[1];
            precise dvec3 half_sum = 0.5lf * sum;
            pos = half_sum;
            // The QEF of the crossings with a normal, in edge order f1, f2 (the CPU's order).
            double qm[9] = double[9](0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
            double qr[3] = double[3](0.0lf, 0.0lf, 0.0lf);
            int normals = 0;
            dvec3 first = dvec3(0.0lf);  // the first kept normal, before its component across the face is zeroed
            for (int m = 0; m < 2; ++m) {
                if (!has_n[m]) continue;
                int g = m == 0 ? f1 : f2;
                int off = m == 0 ? (idx & 1) : ((idx >> 1) & 1);
                ivec3 s = p - off * unit(g);
                dvec3 nn;
                bool cr, os;
                if (!crossing_normal(g, s, inside(s), pts[m][g], nn, cr, os) || cr) continue;  // a crease side: none here
                // The second of two nearly opposite normals: a sheet's other wall (TileContourer::emit_split_face).
                if (normals == 1 && normal_dot(first, nn) < kOpposedNormalCos) continue;
                if (normals == 0) first = nn;
                nn[f] = 0.0lf;
                qef_add(qm, qr, nn, pts[m], half_sum);
                ++normals;
            }
            if (normals > 0) {
                dvec3 corner = dvec3(p);
                dvec3 rlo = min(corner, min(pts[0], pts[1]));
                dvec3 rhi = max(corner, max(pts[0], pts[1]));
                pos = min(max(qef_solve(half_sum, qm, qr, dvec3(fmin)), rlo), rhi);
            }
            precise dvec3 d0 = pts[0] - pos;
            precise dvec3 d1 = pts[1] - pos;
            double e0 = dot3(d0), e1 = dot3(d1);
            mat = mats[0];
            if (e1 < e0 || (e1 == e0 && mats[1] > mat)) mat = mats[1];
        }
        uint v = v0 + uint(idx);
        vtx[v].grid = vec3(pos);
        vtx[v].material = mat;
        vd[3u * v] = pos.x;
        vd[3u * v + 1u] = pos.y;
        vd[3u * v + 2u] = pos.z;
    }
}

// Step 5 for an edge with split faces around it: a fan around the edge's crossing point through the ring
// cells' vertices and the split faces' segment vertices at the edge's inside end (TileContourer::emit_edge).
void emit_fan(ivec3 n, int a, uvec4 reg) {
    bool start_in = inside(n);
    ivec3 inside_end = start_in ? n : n + unit(a);
    uint poly[8];
    int count = 0;
    for (int r = 0; r < 4; ++r) {
        ivec3 cell = ring_cell(n, a, r);
        poly[count++] = vbase(cache_index(cell)) + uint(edge_component(config(cell), ring_local_edge(a, r)));
        ivec3 lower;
        int g;
        ring_face(n, a, r, lower, g);
        uint fi = face_index_of(lower, g);
        if (fi == NONE16) continue;
        uint fs = s_face_base + 4u * fi;
        ivec3 fmin = lower + unit(g);
        int corner = (inside_end[(g + 1) % 3] - fmin[(g + 1) % 3]) + 2 * (inside_end[(g + 2) % 3] - fmin[(g + 2) % 3]);
        poly[count++] = fs + uint(corner);
    }
    if (!start_in)  // outward normal is -a: reverse
        for (int i = 0; i < count / 2; ++i) {
            uint t = poly[i];
            poly[i] = poly[count - 1 - i];
            poly[count - 1 - i] = t;
        }
    uint centre = s_fan_base + atomicAdd(s_fan_cursor, 1u);
    uint em;
    double t = edge_crossing(a, n, start_in, em);
    dvec3 pos = dvec3(n);
    pos[a] = t;
    uint v = reg.x + centre;
    vtx[v].grid = vec3(pos);
    vtx[v].material = em;
    vd[3u * v] = pos.x;
    vd[3u * v + 1u] = pos.y;
    vd[3u * v + 2u] = pos.z;
    uint at = reg.z + atomicAdd(s_icursor, 3u * uint(count));
    for (int i = 0; i < count; ++i) {
        idx[at + 3u * uint(i)] = centre;
        idx[at + 3u * uint(i) + 1u] = poly[i];
        idx[at + 3u * uint(i) + 2u] = poly[(i + 1) % count];
    }
}

