// compute/tools/model_resample.cpp - re-sampling a tri-dexel model onto a finer or coarser lattice over the same box.
#include "compute/tools/model_resample.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>
#include <sstream>
#include <string>

#include "compute/model/volume.hpp"
#include "compute/parallel/task_pool.hpp"
#include "compute/tools/clay_field.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

/// A lateral position closer than this (old cells) to an old ray counts as lying on it.
constexpr double kOnRay = 1e-6;
/// Largest spread (old cells) of the neighbours' matching ends along the ray that is blended: a steeper surface is
/// taken from the field, whose distances come from the rays that cross it squarely.
constexpr float kBlendSpread = 1.0f;
/// Ends of neighbouring old rays closer than this (old cells) lie on one flat face across the rays.
constexpr float kFlatTolerance = 1e-4f;
/// How far (old cells) beyond the nearest old rays' material the field fallback looks for crossings.
constexpr int kFieldReach = 2;

/// New grid units along axis a = old grid units * s + d[a].
struct GridMap {
    double s = 1.0;
    double d[3] = {0.0, 0.0, 0.0};
};

GridMap grid_map(const Lattice& from, const Lattice& to) {
    GridMap m;
    m.s = from.cell_m / to.cell_m;  // exactly 2, 1/2, ... when one spacing is a power-of-two multiple of the other
    for (int a = 0; a < 3; ++a) m.d[a] = (from.origin_m[a] - to.origin_m[a]) / to.cell_m;
    return m;
}

/// One of the (up to four) old rays around a new ray: its intervals, its node and its bilinear weight.
struct Neighbour {
    const std::vector<Interval>* ray = nullptr;
    int nu = 0, nv = 0;
    double w = 0.0;
};

/// Splits an old-grid coordinate into a node index and a fraction in [0, 1), snapping to a node within kOnRay.
void split(double p, int& i, double& f) {
    const double fl = std::floor(p);
    i = static_cast<int>(fl);
    f = p - fl;
    if (f < kOnRay) f = 0.0;
    if (f > 1.0 - kOnRay) {
        i += 1;
        f = 0.0;
    }
}

/// Appends [enter, exit] (new grid units, double) clipped to [0, limit] and rounded to float, merging it with the last
/// interval when they touch, so `out` stays sorted, disjoint and non-touching. Empty pieces are dropped.
void append(std::vector<Interval>& out, double enter, double exit, std::uint8_t me, std::uint8_t mx, double limit) {
    const float e = static_cast<float>(std::max(enter, 0.0));
    const float x = static_cast<float>(std::min(exit, limit));
    if (!(e < x)) return;
    if (!out.empty() && e <= out.back().exit) {
        if (x > out.back().exit) {
            out.back().exit = x;
            out.back().exit_material = mx;
        }
        return;
    }
    out.push_back(Interval{e, x, me, mx});
}

/// True when the neighbours' topology agrees: every one holds the same number of intervals, the k-th intervals of all
/// of them overlap, and so do the k-th gaps between them (so that a blended end lies between ends of one surface), and
/// the k-th ends spread by at most kBlendSpread along the ray.
bool matching(const Neighbour* nb, int n) {
    const std::size_t count = nb[0].ray->size();
    for (int i = 1; i < n; ++i)
        if (nb[i].ray->size() != count) return false;
    for (std::size_t k = 0; k < count; ++k) {
        float lo = (*nb[0].ray)[k].enter, hi = (*nb[0].ray)[k].exit;
        float gap_lo = hi, gap_hi = k + 1 < count ? (*nb[0].ray)[k + 1].enter : 0.0f;
        for (int i = 1; i < n; ++i) {
            const std::vector<Interval>& r = *nb[i].ray;
            lo = std::max(lo, r[k].enter);
            hi = std::min(hi, r[k].exit);
            if (k + 1 < count) {
                gap_lo = std::max(gap_lo, r[k].exit);
                gap_hi = std::min(gap_hi, r[k + 1].enter);
            }
        }
        if (!(lo < hi) || (k + 1 < count && !(gap_lo < gap_hi))) return false;
        float e0 = (*nb[0].ray)[k].enter, e1 = e0, x0 = (*nb[0].ray)[k].exit, x1 = x0;
        for (int i = 1; i < n; ++i) {
            e0 = std::min(e0, (*nb[i].ray)[k].enter), e1 = std::max(e1, (*nb[i].ray)[k].enter);
            x0 = std::min(x0, (*nb[i].ray)[k].exit), x1 = std::max(x1, (*nb[i].ray)[k].exit);
        }
        if (e1 - e0 > kBlendSpread || x1 - x0 > kBlendSpread) return false;
    }
    return true;
}

/// The material of the old surface at grid point (old cells) p[axis] = t, p[ua] = pu, p[va] = pv: that of the interval
/// end nearest to it (in 3D) on the rays of all three sets through the 4 nodes around its projection on each set's
/// plane (a steep surface is crossed nearly square by another set's rays); 0 when none holds an interval.
std::uint8_t material_at(const TriDexel& model, int axis, double t, double pu, double pv) {
    double p[3];
    p[axis] = t;
    p[(axis + 1) % 3] = pu;
    p[(axis + 2) % 3] = pv;
    double best = std::numeric_limits<double>::infinity();
    std::uint8_t m = 0;
    for (int a = 0; a < 3; ++a) {
        const RaySet& set = model.sets[a];
        const double qu = p[(a + 1) % 3], qv = p[(a + 2) % 3];
        const int u0 = static_cast<int>(std::floor(qu)), v0 = static_cast<int>(std::floor(qv));
        for (int v = v0; v <= v0 + 1; ++v)
            for (int u = u0; u <= u0 + 1; ++u) {
                if (u < 0 || u >= set.nu || v < 0 || v >= set.nv) continue;
                const double lat = (u - qu) * (u - qu) + (v - qv) * (v - qv);
                for (const Interval& iv : set.ray(u, v)) {
                    const double de = lat + (iv.enter - p[a]) * (iv.enter - p[a]);
                    const double dx = lat + (iv.exit - p[a]) * (iv.exit - p[a]);
                    if (de < best) best = de, m = iv.enter_material;
                    if (dx < best) best = dx, m = iv.exit_material;
                }
            }
    }
    return m;
}

/// The kField rule: the old model's node field (clay_node_phi) on the neighbours' nodes, blended with their weights
/// at each depth node, and its sign changes as linear roots, over the neighbours' material +- kFieldReach cells.
void field_ray(const TriDexel& model, int axis, double pu, double pv, const Neighbour* nb, int n, const GridMap& map,
               double limit, std::vector<Interval>& out) {
    const Lattice& L = model.lattice;
    double lo_t = std::numeric_limits<double>::infinity(), hi_t = -lo_t;
    for (int i = 0; i < n; ++i)
        if (!nb[i].ray->empty()) {
            lo_t = std::min<double>(lo_t, nb[i].ray->front().enter);
            hi_t = std::max<double>(hi_t, nb[i].ray->back().exit);
        }
    if (!(lo_t <= hi_t)) return;
    const int lo = std::max(0, static_cast<int>(std::floor(lo_t)) - kFieldReach);
    const int hi = std::min(L.cells[axis], static_cast<int>(std::ceil(hi_t)) + kFieldReach);
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const float search = static_cast<float>(kClaySearchCells);
    auto phi = [&](int k) {
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
            int node[3];
            node[axis] = k;
            node[ua] = nb[i].nu;
            node[va] = nb[i].nv;
            const bool on = node[ua] >= 0 && node[ua] <= L.cells[ua] && node[va] >= 0 && node[va] <= L.cells[va];
            sum += nb[i].w * (on ? clay_node_phi(model, node[0], node[1], node[2], search) : search);
        }
        return sum;
    };
    double prev = phi(lo);
    double start = prev < 0.0 ? lo : -1.0;
    for (int k = lo; k < hi; ++k) {
        const double next = phi(k + 1);
        const bool in0 = prev < 0.0, in1 = next < 0.0;
        if (in0 != in1) {
            const double t = k + prev / (prev - next);
            if (in1) {
                start = t;
            } else {
                append(out, start * map.s + map.d[axis], t * map.s + map.d[axis],
                       material_at(model, axis, start, pu, pv), material_at(model, axis, t, pu, pv), limit);
            }
        }
        prev = next;
    }
    if (prev < 0.0)
        append(out, start * map.s + map.d[axis], hi * map.s + map.d[axis], material_at(model, axis, start, pu, pv),
               material_at(model, axis, hi, pu, pv), limit);
}

/// True when the two rays hold the same number of intervals whose ends lie within kFlatTolerance cells of each other.
bool same_ends(const std::vector<Interval>& a, const std::vector<Interval>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k)
        if (std::fabs(a[k].enter - b[k].enter) > kFlatTolerance || std::fabs(a[k].exit - b[k].exit) > kFlatTolerance)
            return false;
    return true;
}

/// The kField intervals `out` (new grid units) with their ends moved onto flat faces across the ray: when the
/// non-empty neighbours all hold the same ends (two or more of them, or one with an old ray beside it that does), the
/// field found as many intervals, and each of its ends lies within kBlendSpread old cells of theirs, the ends become
/// theirs (the field's distances bend round the edge of a face; the face itself is flat up to it).
void snap_to_flat_faces(const TriDexel& model, int axis, const Neighbour* nb, int n, const GridMap& map, double limit,
                        std::vector<Interval>& out) {
    const Neighbour* ref = nullptr;
    int count = 0;
    for (int i = 0; i < n; ++i) {
        if (nb[i].ray->empty()) continue;
        if (!ref) ref = &nb[i];
        if (!same_ends(*ref->ray, *nb[i].ray)) return;
        ++count;
    }
    if (!ref || ref->ray->size() != out.size()) return;
    if (count == 1) {  // one ray: flat only when an old ray beside it holds the same ends
        const RaySet& set = model.sets[axis];
        bool witness = false;
        for (const auto& [du, dv] : {std::pair{-1, 0}, std::pair{1, 0}, std::pair{0, -1}, std::pair{0, 1}}) {
            const int u = ref->nu + du, v = ref->nv + dv;
            if (u >= 0 && u < set.nu && v >= 0 && v < set.nv && same_ends(*ref->ray, set.ray(u, v))) witness = true;
        }
        if (!witness) return;
    }
    std::vector<Interval> snapped;
    const double s = map.s, d = map.d[axis], reach = kBlendSpread * s;
    for (std::size_t k = 0; k < out.size(); ++k) {
        const Interval& f = (*ref->ray)[k];
        const double e = f.enter * s + d, x = f.exit * s + d;
        if (std::fabs(out[k].enter - e) > reach || std::fabs(out[k].exit - x) > reach) return;
        append(snapped, e, x, out[k].enter_material, out[k].exit_material, limit);
    }
    if (snapped.size() == out.size()) out.swap(snapped);
}

}  // namespace

int lattice_resolution(const Lattice& lattice) {
    return std::max({lattice.cells[0], lattice.cells[1], lattice.cells[2]});
}

Lattice resampled_lattice(const Lattice& old, int resolution) {
    if (resolution < kResampleMinResolution || resolution > kResampleMaxResolution)
        throw Error("resample: the resolution must be between " + std::to_string(kResampleMinResolution) + " and " +
                    std::to_string(kResampleMaxResolution) + " cells, got " + std::to_string(resolution));
    const int n = lattice_resolution(old);
    if (resolution == n) return old;
    Lattice l;
    l.cell_m = old.cell_m * (static_cast<double>(n) / resolution);
    for (int a = 0; a < 3; ++a) {
        const long long num = static_cast<long long>(old.cells[a]) * resolution;
        l.cells[a] = std::max(1, static_cast<int>((num + n - 1) / n));                 // ceil(cells * N' / N), exact
        const double pad = 0.5 * (l.cells[a] * l.cell_m - old.cells[a] * old.cell_m);  // centre on the old box
        l.origin_m[a] = old.origin_m[a] - pad;
    }
    return l;
}

std::size_t resample_bytes_estimate(const TriDexel& model, const Lattice& target) {
    double rays_old = 0.0, rays_new = 0.0;
    for (int a = 0; a < 3; ++a) {
        rays_old += static_cast<double>(model.lattice.nodes((a + 1) % 3)) * model.lattice.nodes((a + 2) % 3);
        rays_new += static_cast<double>(target.nodes((a + 1) % 3)) * target.nodes((a + 2) % 3);
    }
    const double intervals =
        std::max(2.0 * rays_new, static_cast<double>(model.interval_count()) * rays_new / std::max(rays_old, 1.0));
    const double bytes = rays_new * sizeof(std::vector<Interval>) + intervals * sizeof(Interval);
    return bytes >= 1.8e19 ? static_cast<std::size_t>(-1) : static_cast<std::size_t>(bytes);
}

ResampledRay resample_ray(const TriDexel& model, const Lattice& target, int axis, int u, int v,
                          std::vector<Interval>& out) {
    out.clear();
    static const std::vector<Interval> kNone;
    const GridMap map = grid_map(model.lattice, target);
    const int ua = (axis + 1) % 3, va = (axis + 2) % 3;
    const double pu = (u - map.d[ua]) / map.s, pv = (v - map.d[va]) / map.s;  // the new ray in old cells
    int iu, iv;
    double fu, fv;
    split(pu, iu, fu);
    split(pv, iv, fv);
    const RaySet& set = model.sets[axis];
    Neighbour nb[4];
    int n = 0;
    for (int dv = 0; dv <= (fv > 0.0 ? 1 : 0); ++dv)
        for (int du = 0; du <= (fu > 0.0 ? 1 : 0); ++du) {
            Neighbour& x = nb[n++];
            x.nu = iu + du;
            x.nv = iv + dv;
            x.w = (du ? fu : 1.0 - fu) * (dv ? fv : 1.0 - fv);
            const bool on = x.nu >= 0 && x.nu < set.nu && x.nv >= 0 && x.nv < set.nv;
            x.ray = on ? &set.ray(x.nu, x.nv) : &kNone;
        }
    const double limit = target.cells[axis];
    const double s = map.s, d = map.d[axis];
    if (n == 1) {  // on an old ray: its intervals, depths mapped (exactly, for power-of-two ratios)
        for (const Interval& x : *nb[0].ray)
            append(out, x.enter * s + d, x.exit * s + d, x.enter_material, x.exit_material, limit);
        return ResampledRay::kCopied;
    }
    if (matching(nb, n)) {  // the same intervals on every neighbour: their ends blended, the nearest ends' materials
        for (std::size_t k = 0; k < nb[0].ray->size(); ++k) {
            double e = 0.0, x = 0.0;
            for (int i = 0; i < n; ++i) {
                e += nb[i].w * (*nb[i].ray)[k].enter;
                x += nb[i].w * (*nb[i].ray)[k].exit;
            }
            append(out, e * s + d, x * s + d, material_at(model, axis, e, pu, pv), material_at(model, axis, x, pu, pv),
                   limit);
        }
        return ResampledRay::kBlended;
    }
    field_ray(model, axis, pu, pv, nb, n, map, limit, out);
    snap_to_flat_faces(model, axis, nb, n, map, limit, out);
    return ResampledRay::kField;
}

TriDexel resample_model(const TriDexel& model, int resolution, std::size_t max_bytes, ResampleStats* stats) {
    const Lattice target = resampled_lattice(model.lattice, resolution);
    const int before = lattice_resolution(model.lattice);
    ResampleStats st;
    st.resolution_before = before;
    st.resolution_after = resolution;
    st.cell_before_m = model.lattice.cell_m;
    st.cell_after_m = target.cell_m;
    st.bytes_after = resample_bytes_estimate(model, target);
    if (resolution == before) {
        st.identical = true;
        if (stats) {
            st.volume_before_m3 = st.volume_after_m3 = dexel_volume_m3(model);
            *stats = st;
        }
        return model;
    }
    if (st.bytes_after > max_bytes) {
        std::ostringstream msg;
        msg << "resample: resolution " << resolution << " (" << target.cells[0] << "x" << target.cells[1] << "x"
            << target.cells[2] << " cells) needs about " << st.bytes_after / (1024 * 1024) << " MiB, more than the "
            << max_bytes / (1024 * 1024) << " MiB available; choose a lower resolution";
        throw Error(msg.str());
    }
    TriDexel out = TriDexel::empty(target, max_bytes);
    // Every ray on its own (it reads only the old model), so rows of rays run on every core with the same result.
    std::atomic<std::size_t> copied{0}, blended{0}, field{0};
    for (int a = 0; a < 3; ++a) {
        RaySet& set = out.sets[a];
        pool_for(static_cast<std::size_t>(set.nv), 1, [&](const Chunk& c) {
            std::size_t n[3] = {0, 0, 0};
            for (std::size_t v = c.first; v < c.last; ++v)
                for (int u = 0; u < set.nu; ++u)
                    ++n[static_cast<int>(resample_ray(model, target, a, u, static_cast<int>(v), set.ray(u, static_cast<int>(v))))];
            copied += n[static_cast<int>(ResampledRay::kCopied)];
            blended += n[static_cast<int>(ResampledRay::kBlended)];
            field += n[static_cast<int>(ResampledRay::kField)];
        });
    }
    st.rays_copied = copied;
    st.rays_blended = blended;
    st.rays_field = field;
    std::fill(out.tiles.dirty.begin(), out.tiles.dirty.end(), TileGrid::kWhole);
    if (stats) {
        st.volume_before_m3 = dexel_volume_m3(model);
        st.volume_after_m3 = dexel_volume_m3(out);
        *stats = st;
    }
    return out;
}

}  // namespace tridex::compute
