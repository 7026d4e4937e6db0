// app/session/report/strip_moments.cpp - what each journal record changed, and the pictures spread over the change.
#include "app/session/report/strip_moments.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>

namespace tridex::app {

namespace {

// A 32-bit digest of each ray of the three sets (FNV-1a over its interval ends and their materials), kept up to date
// over the rays that cross the dirty tiles, to tell how many rays a record rewrote.
class RayDigests {
public:
    explicit RayDigests(const compute::TriDexel& m) {
        for (int a = 0; a < 3; ++a) {
            const auto& rays = m.sets[a].rays;
            digest_[a].resize(rays.size());
            stamp_[a].assign(rays.size(), 0);
            for (std::size_t r = 0; r < rays.size(); ++r) digest_[a][r] = digest(rays[r]);
        }
    }

    // The rays crossing m's dirty tiles whose content changed since the last look; refreshes them. `stamp` must
    // differ from every earlier call's.
    std::size_t refresh(const compute::TriDexel& m, std::uint32_t stamp) {
        const compute::TileGrid& g = m.tiles;
        const std::size_t nx = static_cast<std::size_t>(g.tiles[0]), ny = static_cast<std::size_t>(g.tiles[1]);
        std::size_t changed = 0;
        for (std::size_t t = 0; t < g.dirty.size(); ++t) {
            if (g.dirty[t] == 0) continue;
            const std::array<int, 3> tile{static_cast<int>(t % nx), static_cast<int>(t / nx % ny),
                                          static_cast<int>(t / (nx * ny))};
            for (int a = 0; a < 3; ++a) changed += refresh_set(m.sets[a], tile, stamp);
        }
        return changed;
    }

private:
    static std::uint32_t digest(const std::vector<compute::Interval>& ray) {
        std::uint32_t h = 2166136261u;
        const auto mix = [&h](const void* p, std::size_t n) {
            for (std::size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 16777619u;
        };
        for (const compute::Interval& iv : ray) {
            mix(&iv.enter, sizeof iv.enter);
            mix(&iv.exit, sizeof iv.exit);
            mix(&iv.enter_material, 1);
            mix(&iv.exit_material, 1);
        }
        return h;
    }

    // The rays of `set` whose nodes lie on the tile's cells (corner nodes included).
    std::size_t refresh_set(const compute::RaySet& set, const std::array<int, 3>& tile, std::uint32_t stamp) {
        constexpr int kT = compute::TileGrid::kTileCells;
        const int a = set.axis, ub = (a + 1) % 3, vb = (a + 2) % 3;
        const int u0 = tile[ub] * kT, u1 = std::min(u0 + kT, set.nu - 1);
        const int v0 = tile[vb] * kT, v1 = std::min(v0 + kT, set.nv - 1);
        std::size_t changed = 0;
        for (int v = v0; v <= v1; ++v)
            for (int u = u0; u <= u1; ++u) {
                const std::size_t r =
                    static_cast<std::size_t>(u) + static_cast<std::size_t>(set.nu) * static_cast<std::size_t>(v);
                if (stamp_[a][r] == stamp) continue;
                stamp_[a][r] = stamp;
                const std::uint32_t now = digest(set.rays[r]);
                changed += now != digest_[a][r];
                digest_[a][r] = now;
            }
        return changed;
    }

    std::array<std::vector<std::uint32_t>, 3> digest_;
    std::array<std::vector<std::uint32_t>, 3> stamp_;
};

}  // namespace

compute::Journal split_batches(const compute::Journal& journal, std::size_t max_samples) {
    compute::Journal out;
    out.version = journal.version;
    out.session = journal.session;
    out.samples = journal.samples;
    out.file_bytes = journal.file_bytes;
    const std::size_t piece = std::max<std::size_t>(1, max_samples);
    const auto add = [&](compute::JournalRecord r) {
        r.index = out.records.size();
        out.records.push_back(std::move(r));
    };
    for (const compute::JournalRecord& r : journal.records) {
        if (r.kind != compute::JournalKind::kBatch || r.samples.size() <= piece) {
            add(r);
            continue;
        }
        for (std::size_t i = 0; i < r.samples.size(); i += piece) {
            compute::JournalRecord part = r;
            part.samples.assign(r.samples.begin() + static_cast<std::ptrdiff_t>(i),
                                r.samples.begin() + static_cast<std::ptrdiff_t>(std::min(r.samples.size(), i + piece)));
            add(std::move(part));
        }
    }
    return out;
}

compute::JournalApplyFrom strip_replay(compute::JournalApplyFrom replay) {
    replay.record = 0;
    replay.last_serial = 0;
    replay.history_budget_bytes = std::size_t{1} << 40;
    return replay;
}

std::vector<double> record_changes(const compute::Journal& journal, const compute::TriDexel& start,
                                   const compute::JournalApplyFrom& from, const ProgressFn& progress) {
    compute::TriDexel model = start;
    compute::JournalApplier applier(model, from);
    RayDigests digests(model);
    const std::size_t n = journal.records.size();
    std::vector<double> rewritten(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
        model.clear_dirty();
        applier.apply(std::span<const compute::JournalRecord>(&journal.records[k], 1));
        if (std::any_of(model.tiles.dirty.begin(), model.tiles.dirty.end(), [](std::uint8_t d) { return d != 0; }))
            rewritten[k] = static_cast<double>(digests.refresh(model, static_cast<std::uint32_t>(k + 1)));
        report_progress(progress, static_cast<double>(k + 1), static_cast<double>(n));
    }
    return rewritten;
}

std::vector<std::size_t> strip_picture_records(const compute::Journal& j, const std::vector<double>& change,
                                               int frames) {
    const std::size_t n = j.records.size();
    std::vector<std::uint64_t> samples_before(n + 1, 0);  // samples in records [0, k)
    std::size_t first_op = n, last_change = n;
    double total = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        samples_before[k + 1] = samples_before[k] + j.records[k].samples.size();
        if (first_op == n)
            for (const ToolSample& s : j.records[k].samples)
                if (s.op != ToolOp::kNone) first_op = k;
        const double c = k < change.size() ? change[k] : 0.0;
        if (c > 0.0) {
            total += c;
            last_change = k;
        }
    }
    // The span the pictures cover, in records applied: from_k .. to_k.
    std::size_t from_k = first_op, to_k = n;
    if (total > 0.0) {
        double so_far = 0.0;
        for (from_k = 0; from_k < n; ++from_k) {
            so_far += from_k < change.size() ? change[from_k] : 0.0;
            if (so_far > kStripLeadShare * total) break;  // record from_k passes the lead share
        }
        to_k = last_change + 1;
    }
    from_k = std::min(from_k, to_k);
    const std::uint64_t from = samples_before[from_k], to = samples_before[to_k];
    std::vector<std::size_t> out;
    for (int i = 0; i < frames; ++i) {
        if (i == 0 || i == frames - 1) {  // the ends exactly: a mark (an undo, a redo) holds no sample to aim at
            out.push_back(i == 0 ? from_k : to_k);
            continue;
        }
        const std::uint64_t want =
            from + (to - from) * static_cast<std::uint64_t>(i) / static_cast<std::uint64_t>(frames - 1);
        // The first k whose samples_before reaches `want` (records are applied whole).
        const auto it = std::lower_bound(samples_before.begin() + static_cast<std::ptrdiff_t>(from_k),
                                         samples_before.begin() + static_cast<std::ptrdiff_t>(to_k) + 1, want);
        out.push_back(static_cast<std::size_t>(it - samples_before.begin()));
    }
    return out;
}

}  // namespace tridex::app
