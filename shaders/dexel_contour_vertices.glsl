// shaders/dexel_contour_vertices.glsl - part of dexel_contour.comp: the dual vertices of one cell (one per
// surface component, placed by the QEF of its crossings and their normals from neighbouring rays, relative
// to and falling back on their mean, clamped into the cell (dexel_contour_qef.glsl); nearest-crossing material).

// Start node of the cell's edge e = 4a + k along axis a, as an offset from the cell's min node
// (contour_table.hpp numbering: bit 0 of k steps along (a + 1) % 3, bit 1 along (a + 2) % 3).
ivec3 edge_start_offset(int a, int k) {
    ivec3 off = ivec3(0);
    off[(a + 1) % 3] = k & 1;
    off[(a + 2) % 3] = (k >> 1) & 1;
    return off;
}

// Dot product of two normals, summed in the CPU's order (contour_tile.cpp normal_dot).
double normal_dot(dvec3 a, dvec3 b) {
    precise double d = (a.x * b.x + a.y * b.y) + a.z * b.z;
    return d;
}

// contour_tile.cpp node_inside: occupancy of node n read from its X ray (enter <= x < exit; boundary and outside
// nodes outside), for nodes beyond the tile's occupancy block.
bool node_inside_ray(ivec3 n) {
    if (any(lessThan(n, ivec3(1))) || any(greaterThan(n, pc.cells.xyz - ivec3(1)))) return false;
    uint r = uint(n.y) + uint(pc.cells.y + 1) * uint(n.z);
    uint m = ray_meta(0, r), cnt = m & 127u;
    double x = double(n.x);
    for (uint i = 0u; i < cnt; ++i) {
        float en, ex;
        uint pair;
        ray_interval(0, r, m, i, en, ex, pair);
        if (!(en <= ex)) continue;
        if (double(en) <= x && x < double(ex)) return true;
    }
    return false;
}

// Node occupancy for neighbour_planes: from the tile's occupancy block where it holds n (no loop, so dense tiles stay
// within llvmpipe's loop cap), else node_inside_ray (the same definition).
bool node_inside_near(ivec3 n) {
    ivec3 d = n - lo;
    if (all(greaterThanEqual(d, ivec3(0))) && all(lessThan(d, ivec3(SPAN)))) return inside(n);
    return node_inside_ray(n);
}

// place_vertices' crossing depths and normals per cell edge, invocation-private globals so that neighbour_planes
// reads and writes them in place (as array parameters they were copied at every call, which slowed the whole
// kernel).
double tq[12];
dvec3 nq[12];

// The crossings with an ordinary normal on the edges of the 6 cells face-adjacent to `cell` off the shared faces
// (face f, side -1 then +1, edges ascending), for two rules that share this one loop (one call site in
// place_vertices; a component needs at most one of them):
// - borrow (contour_tile.cpp borrowed_normals): for each edge e of `own` (the component's edges; crossing at tq[e],
//   leaving material going +axis when cfg's start corner is inside), among the normals pointing out of the material
//   along e's axis, the one whose tangent plane passes nearest to the crossing (first on ties), within kBorrowReach:
//   into nq[e], its bit into `got`; for an edge of `kept` (its own normal in nq[e] stays) only its bit into `got`,
//   and into `against` whether that normal makes a dot product below kBorrowWrongCos with the own one; returns false;
// - corner fill (contour_tile.cpp corner_fill_plane): among those whose normal's dot product with each normal nq[e]
//   of `own` (edge bits) exceeds kCornerFillCos and whose plane has `mass` in front or at most kCornerFillFront behind,
//   the tangent plane `pos` lies deepest behind (first on ties); true with its point and normal when deeper than
//   kCornerFillDepth.
bool neighbour_planes(ivec3 cell, bool borrow, int cfg, uint own, uint kept, dvec3 pos, dvec3 mass, out dvec3 point,
                      out dvec3 normal, out uint got, out uint against) {
    bool found = false;
    double deepest = 0.0lf;
    point = dvec3(0.0lf);
    normal = dvec3(0.0lf);
    got = 0u;
    against = 0u;
    double best[12];
    [[unroll]] for (int e = 0; e < 12; ++e) best[e] = 0.0lf;
    [[dont_unroll]] for (int f = 0; f < 3; ++f) {
        [[dont_unroll]] for (int side = -1; side <= 1; side += 2) {
            ivec3 nb = cell;
            nb[f] += side;
            int face = side > 0 ? cell[f] + 1 : cell[f];
            [[dont_unroll]] for (int e = 0; e < 12; ++e) {
                const int a = e / 4;
                ivec3 p = nb + edge_start_offset(a, e & 3);
                if (a != f && p[f] == face) continue;
                ivec3 q = p + unit(a);
                if (any(lessThan(p, ivec3(0))) || any(greaterThan(q, pc.cells.xyz))) continue;
                bool pin = node_inside_near(p);
                if (pin == node_inside_near(q)) continue;
                uint mat;
                bool fb, ex;
                double t = edge_crossing(a, p, pin, mat, fb, ex);
                if (fb || ex != pin) continue;
                dvec3 nn;
                bool cr, os;
                if (!crossing_normal(a, p, pin, t, nn, cr, os) || cr) continue;
                dvec3 cp = dvec3(p);
                cp[a] = t;
                if (borrow) {
                    uint om = own;
                    while (om != 0u) {
                        int i = findLSB(om);
                        om &= om - 1u;
                        const int ia = i / 4;
                        const ivec3 off = edge_start_offset(ia, i & 3);
                        const bool exits = ((cfg >> (off.x + 2 * off.y + 4 * off.z)) & 1) != 0;
                        double along = nn[ia];
                        if (!(exits ? along > 0.0lf : along < 0.0lf)) continue;
                        dvec3 x = dvec3(cell + off);
                        x[ia] = tq[i];
                        precise dvec3 d = x - cp;
                        double r = abs(normal_dot(nn, d));
                        if (!(r <= kBorrowReach)) continue;
                        if (((got >> uint(i)) & 1u) == 0u || r < best[i]) {
                            got |= 1u << uint(i);
                            best[i] = r;
                            if (((kept >> uint(i)) & 1u) == 0u)
                                nq[i] = nn;
                            else if (normal_dot(nn, nq[i]) < kBorrowWrongCos)
                                against |= 1u << uint(i);
                            else
                                against &= ~(1u << uint(i));
                        }
                    }
                    continue;
                }
                bool fits = true;
                uint om = own;
                while (om != 0u) {
                    int i = findLSB(om);
                    om &= om - 1u;
                    if (!(normal_dot(nn, nq[i]) > kCornerFillCos)) fits = false;
                }
                if (!fits) continue;
                precise dvec3 dm = mass - cp;
                if (!(normal_dot(nn, dm) >= -kCornerFillFront)) continue;
                precise dvec3 d = pos - cp;
                precise double depth = -((nn.x * d.x + nn.y * d.y) + nn.z * d.z);
                if (!found || depth > deepest) {
                    found = true;
                    deepest = depth;
                    point = cp;
                    normal = nn;
                }
            }
        }
    }
    return found && deepest > kCornerFillDepth;
}

// The vertices of used cell `cell` (TileContourer::cell_vertices) into slots base .. base + components - 1.
// The expensive per-edge work (crossings, normals) runs in per-axis dynamic loops over the edges this cell
// needs, so SIMD lanes share iterations (llvmpipe runs 8 invocations per lane group); the cheap sums are
// unrolled over the 12 edges. All sums run in the CPU's order (ascending edge per component), so the
// doubles are the same. Each edge belongs to one component, so its normal is estimated once, in that
// component's pass.
void place_vertices(ivec3 cell, uint base) {
    int cfg = config(cell);
    int comps = components(cfg);
    uint mq[12];
    int cq[12];
    bool fq[12];
    uint crossed = 0u;
    [[unroll]] for (int e = 0; e < 12; ++e) {
        cq[e] = edge_component(cfg, e);
        tq[e] = 0.0lf;
        mq[e] = 0u;
        fq[e] = true;
        if (cq[e] >= 0) crossed |= 1u << uint(e);
    }
    // The crossings, per axis a dynamic loop over the crossed edges e = 4a + k (see the normals below).
    [[unroll]] for (int a = 0; a < 3; ++a) {
        uint todo = (crossed >> uint(4 * a)) & 15u;
        while (todo != 0u) {
            int k = findLSB(todo);
            todo &= todo - 1u;
            const ivec3 off = edge_start_offset(a, k);
            const int corner = off.x + 2 * off.y + 4 * off.z;
            uint m;
            bool fb, ex;
            const bool start_in = ((cfg >> corner) & 1) != 0;
            tq[4 * a + k] = edge_crossing(a, cell + off, start_in, m, fb, ex);
            mq[4 * a + k] = m;
            fq[4 * a + k] = fb || ex != start_in;  // no normal: a fallback, or not the kind the occupancy implies
        }
    }
    dvec3 clo = dvec3(cell);
    uint voff = region[job_tile[pc.job_base + gl_WorkGroupID.x]].x;
    [[dont_unroll]] for (int c = 0; c < 4; ++c) {
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
        // The QEF of the component's crossings in ascending edge order with their own normals (not fallbacks);
        // when only some have one, the others take the normal of the plane fitted to all (contour::fit_normal).
        // Per axis a, a dynamic loop over this component's edges e = 4a + k that may have a normal: the
        // invocations running together in SIMD lanes share the iterations instead of each paying for every
        // edge that any of them crosses.
        uint mine = 0u;
        [[unroll]] for (int e = 0; e < 12; ++e)
            if (cq[e] == c && !fq[e]) mine |= 1u << uint(e);
        [[unroll]] for (int e = 0; e < 12; ++e) nq[e] = dvec3(0.0lf);
        uint has = 0u, creased = 0u, lone = 0u;
        [[unroll]] for (int a = 0; a < 3; ++a) {
            uint todo = (mine >> uint(4 * a)) & 15u;
            while (todo != 0u) {
                int k = findLSB(todo);
                todo &= todo - 1u;
                const ivec3 off = edge_start_offset(a, k);
                const int corner = off.x + 2 * off.y + 4 * off.z;
                dvec3 nn;
                bool cr, os;
                if (!crossing_normal(a, cell + off, ((cfg >> corner) & 1) != 0, tq[4 * a + k], nn, cr, os)) continue;
                nq[4 * a + k] = nn;
                has |= 1u << uint(4 * a + k);
                if (cr) creased |= 1u << uint(4 * a + k);
                if (os) lone |= 1u << uint(4 * a + k);
            }
        }
        // Normals from a crease's flat side count where no crossing has a normal of its own kind; beside such
        // normals only when each makes an acute angle with every one of them (contour_tile.cpp crease_normal_fits:
        // dot > 0, same order) and the vertex placed with them lies within kCreaseResidual of each of their
        // tangent planes; else the vertex is placed again without them (TileContourer::cell_vertices).
        uint plain = has & ~creased;
        bool agree = true;
        uint ci = creased;
        while (ci != 0u) {
            int e = findLSB(ci);
            ci &= ci - 1u;
            uint pj = plain;
            while (pj != 0u) {
                int f = findLSB(pj);
                pj &= pj - 1u;
                double d = normal_dot(nq[e], nq[f]);
                if (!(d > 0.0lf)) agree = false;
            }
        }
        bool try_crease = plain != 0u && creased != 0u && agree;
        // The component's crossings (ascending edge), for the fitted plane when only some have a normal.
        dvec3 fpts[12];
        int faxes[12];
        bool fexits[12];
        int nc = 0;
        [[unroll]] for (int e = 0; e < 12; ++e) {
            if (cq[e] != c) continue;
            const int a = e / 4;
            const ivec3 off = edge_start_offset(a, e & 3);
            dvec3 q = dvec3(cell + off);
            q[a] = tq[e];
            fpts[nc] = q;
            faxes[nc] = a;
            fexits[nc] = ((cfg >> (off.x + 2 * off.y + 4 * off.z)) & 1) != 0;
            ++nc;
        }
        dvec3 pos = dvec3(0.0lf);
        double qm[9];
        double qr[3];
        // Round 0: a component without any normal borrows the face-adjacent cells' (contour::kBorrowReach); one whose
        // normals all took a slope from one side alone, a single normal or, without crease normals, one beside a
        // crossing without one on a parallel edge of the cell, only when the normal borrowed for one of its own crossings disagrees with that crossing's
        // (contour::kBorrowWrongCos; the own normals are kept); then the vertex is placed. Round 1 (only when some
        // invocation needs it): the corner fill (contour::kCornerFillReach), a concave crease vertex far behind its
        // crossings' mass point, cut off by a neighbouring cell's tangent plane, is placed again with that plane
        // (TileContourer). Both rules read the neighbours through neighbour_planes.
        uint cmask = 0u;
        [[unroll]] for (int e = 0; e < 12; ++e)
            if (cq[e] == c) cmask |= 1u << uint(e);
        // A crossing without a normal on a parallel edge of the cell beside an own normal's (TileContourer).
        bool beside = false;
        uint hb = has;
        while (hb != 0u) {
            const int e = findLSB(hb);
            hb &= hb - 1u;
            const int a = e / 4, k = e & 3;
            const uint adjacent = (1u << uint(4 * a + (k ^ 1))) | (1u << uint(4 * a + (k ^ 2)));
            if ((cmask & ~has & adjacent) != 0u) beside = true;
        }
        const bool all_lone = (has & ~lone) == 0u;
        const bool need_borrow = has == 0u || (all_lone && (bitCount(has) == 1 || (creased == 0u && beside)));
        bool fill = false;
        [[dont_unroll]] for (int round = 0; round < 2; ++round) {
            dvec3 cut_p, cut_n;
            uint got = 0u, against = 0u;
            bool cut = false;
            if (round == 0 ? need_borrow : fill)
                cut = neighbour_planes(cell, round == 0, cfg, round == 0 ? cmask : has, round == 0 ? has : 0u, pos, mean, cut_p,
                                       cut_n, got, against);
            if (round == 1) {
                if (cut) {
                    qef_add(qm, qr, cut_n, cut_p, mean);
                    pos = qef_solve(mean, qm, qr, clo);
                }
                break;
            }
            // The own normals stay; a borrowed one that contradicts one of them lets the others borrow.
            uint lent = 0u;
            if (need_borrow && (has == 0u || against != 0u)) {
                lent = got & ~has;
                has |= lent;
            }
            // Borrowed normals may come from both walls of a gap narrower than the cell: of each pair at an obtuse
            // angle, only the wall with more of them is kept (contour::kBorrowSheetCos).
            const double sheet_cos = lent != 0u ? kBorrowSheetCos : kOpposedNormalCos;
            [[dont_unroll]] for (int pass = 0; pass < 2; ++pass) {
                // Pass 0: with the crease normals when try_crease, else the final choice; pass 1: without them.
                uint use = pass == 1 ? plain : (try_crease ? has : (plain != 0u ? plain | lent : has));
                qm = double[9](0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
                qr = double[3](0.0lf, 0.0lf, 0.0lf);
                int normals = 0;
                // Two facing walls of a sheet thinner than the cell (a normal pair's dot below kOpposedNormalCos): only
                // the normals of the wall with more of them (ties: the first's), and no fitted plane.
                bool sheet = false;
                uint ui = use;
                while (ui != 0u) {
                    int e = findLSB(ui);
                    ui &= ui - 1u;
                    uint uj = ui;
                    while (uj != 0u) {
                        int f = findLSB(uj);
                        uj &= uj - 1u;
                        double d = normal_dot(nq[e], nq[f]);
                        if (d < sheet_cos) sheet = true;
                    }
                }
                if (sheet) {
                    int first = findLSB(use);
                    int same = 0, other = 0;
                    uint uk = use;
                    while (uk != 0u) {
                        int e = findLSB(uk);
                        uk &= uk - 1u;
                        double d = normal_dot(nq[e], nq[first]);
                        if (d >= 0.0lf) ++same;
                        else ++other;
                    }
                    bool keep_first = same >= other;
                    uk = use;
                    while (uk != 0u) {
                        int e = findLSB(uk);
                        uk &= uk - 1u;
                        double d = normal_dot(nq[e], nq[first]);
                        if ((d >= 0.0lf) != keep_first) use &= ~(1u << uint(e));
                    }
                }
                int own = bitCount(use);
                dvec3 fitted = dvec3(0.0lf);
                bool fit = !sheet && own > 0 && own < nc && fit_normal(mean, fpts, faxes, fexits, nc, fitted);
                [[unroll]] for (int e = 0; e < 12; ++e) {
                    if (cq[e] != c) continue;
                    bool mine_n = ((use >> uint(e)) & 1u) != 0u;
                    if (!mine_n && !fit) continue;
                    const int a = e / 4;
                    const ivec3 off = edge_start_offset(a, e & 3);
                    dvec3 q = dvec3(cell + off);
                    q[a] = tq[e];
                    qef_add(qm, qr, mine_n ? nq[e] : fitted, q, mean);
                    ++normals;
                }
                pos = normals > 0 ? qef_solve(mean, qm, qr, clo) : min(max(mean, clo), clo + dvec3(1.0lf));
                if (pass == 1 || !try_crease) break;
                // The crease normals stay when the vertex is within kCreaseResidual of every ordinary normal's plane.
                double worst = 0.0lf;
                uint pk = plain;
                while (pk != 0u) {
                    int e = findLSB(pk);
                    pk &= pk - 1u;
                    const int a = e / 4;
                    const ivec3 off = edge_start_offset(a, e & 3);
                    dvec3 q = dvec3(cell + off);
                    q[a] = tq[e];
                    precise dvec3 d = pos - q;
                    precise double r = abs((nq[e].x * d.x + nq[e].y * d.y) + nq[e].z * d.z);
                    if (r > worst) worst = r;
                }
                if (worst <= kCreaseResidual) break;
            }
            if (bitCount(plain) >= 2) {
                precise dvec3 nsum = dvec3(0.0lf);
                uint hk = has;
                while (hk != 0u) {
                    int e = findLSB(hk);
                    hk &= hk - 1u;
                    precise dvec3 ns = nsum + nq[e];
                    nsum = ns;
                }
                precise dvec3 off = pos - mean;
                fill = normal_dot(off, off) > kCornerFillReach * kCornerFillReach && normal_dot(nsum, off) < 0.0lf;
            }
            if (!fill) break;
        }
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

