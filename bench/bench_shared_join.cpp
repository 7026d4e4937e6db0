// bench/bench_shared_join.cpp - `tridex bench --shared`'s late joins: what a joiner arriving after minutes of
// sculpting receives (the stream's bytes) and how long it takes to replay it and contour the result.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/session/shared/shared_message.hpp"
#include "app/support/json_file.hpp"
#include "bench/bench_shared.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/stream_pack.hpp"
#include "compute/history/undo_history.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/tdx_file.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

namespace tridex::bench {

namespace {

using Clock = std::chrono::steady_clock;

// `minutes` of one person sculpting, as the host's stream holds it: records of 1000 samples (a sculpt step's worth at
// most), the tool circling over the top face 1 mm deep, lifted for a sample every 10 s (a stroke each). Marked as
// tails, so a replay closes the strokes where the tool lifts, as the sculpt thread did.
std::vector<compute::JournalRecord> scripted_stream(double minutes) {
    const std::size_t n = static_cast<std::size_t>(minutes * 60e3);
    std::vector<compute::JournalRecord> out;
    for (std::size_t i = 0; i < n; ++i) {
        if (i % 1000 == 0) {
            out.emplace_back().tail = true;
            out.back().index = out.size() - 1;
        }
        ToolSample s;
        s.t_s = 1e-3 * static_cast<double>(i);
        const double a = 0.9 * s.t_s, r = 0.01 + 0.025 * (0.5 + 0.5 * std::sin(0.07 * s.t_s));
        s.position = Vec3(r * std::cos(a), r * std::sin(a), 0.0477);
        s.tool.radius_m = 0.003;
        s.op = i % 10000 == 9999 ? ToolOp::kNone : ToolOp::kSubtract;
        out.back().samples.push_back(s);
    }
    return out;
}

// A join with the model as it stands, timed: at the host, the snapshot (a copy of the model, the history's steps) and
// what its network thread makes of it (the .tdx, the packed history); at the joiner, loading both and contouring.
// Fills the row's model_bytes, packed_history_bytes, snapshot_s and join_load_s.
void time_snapshot_join(const compute::TriDexel& model, const compute::JournalApplier& applier,
                        const std::filesystem::path& dir, LateJoinRow& row) {
    const std::filesystem::path tdx = dir / "shared_late_join_model.tdx";
    const auto t0 = Clock::now();
    compute::TriDexel copy = model;
    std::fill(copy.tiles.dirty.begin(), copy.tiles.dirty.end(), compute::TileGrid::kWhole);  // as take_snapshot does
    const std::vector<unsigned char> steps = applier.history_steps();
    compute::save_tdx(tdx.string(), copy, Mat4(1.0), "{}");
    const std::vector<unsigned char> packed = compute::pack_bytes(steps);
    const auto t1 = Clock::now();
    compute::TdxModel joined = compute::load_tdx(tdx.string(), std::size_t{1} << 31);
    compute::UndoHistory history(joined.model.lattice);
    history.load_steps(compute::unpack_bytes(packed, std::size_t{1} << 30, "the late join's history"));
    compute::Contourer contourer(joined.model);
    contourer.update(joined.model);
    const auto t2 = Clock::now();
    row.model_bytes = std::filesystem::file_size(tdx);
    std::filesystem::remove(tdx);
    row.packed_history_bytes = packed.size();
    row.snapshot_s = std::chrono::duration<double>(t1 - t0).count();
    row.join_load_s = std::chrono::duration<double>(t2 - t1).count();
}

}  // namespace

std::vector<LateJoinRow> run_late_join_bench(const SharedBenchOptions& o) {
    std::vector<LateJoinRow> rows;
    if (o.join_minutes.empty()) return rows;
    std::filesystem::create_directories(o.out);
    std::printf("late join (box at %d cells). From the start: the starting model plus the stream since, replayed by the "
                "host's rules and contoured (what a cluster wall asks for). As it stands: the host's snapshot (model copy, "
                "history, .tdx, packed), then the joiner's load of both and contour (what a joiner gets). Times are "
                "timed; the transfer is the bytes at 10 MB/s\n",
                o.resolution);
    std::printf("%8s %10s | %10s %10s %10s %12s | %10s %10s %10s %10s %12s\n", "minutes", "samples", "stream MB",
                "replay s", "contour s", "at 10 MB/s s", "model MB", "history MB", "snapshot s", "load s", "at 10 MB/s s");
    nlohmann::json js = nlohmann::json::array();
    for (const double minutes : o.join_minutes) {
        if (!(minutes >= 1.0 && minutes <= 60.0)) throw Error("--shared-join-minutes: each must be in [1, 60]");
        LateJoinRow row;
        row.minutes = minutes;
        const std::vector<compute::JournalRecord> stream = scripted_stream(minutes);
        for (std::size_t k = 0; k < stream.size(); k += 2048) {  // as the host sends a backlog
            app::RecordsMessage m;
            m.records.assign(stream.begin() + static_cast<std::ptrdiff_t>(k),
                             stream.begin() + static_cast<std::ptrdiff_t>(std::min(stream.size(), k + 2048)));
            row.bytes += app::encode_records(m).size();
            for (const compute::JournalRecord& r : m.records) row.samples += r.samples.size();
        }
        compute::TriDexel model = compute::TriDexel::empty(
            compute::Lattice::around(Aabb{Vec3(-0.05), Vec3(0.05)}, o.resolution), std::size_t{1} << 31);
        compute::scan_convert(box_mesh(Aabb{Vec3(-0.0487), Vec3(0.0487)}), model);
        const auto t0 = Clock::now();
        compute::JournalApplier applier(model);
        applier.apply(stream);
        applier.flush();
        const auto t1 = Clock::now();
        row.history_bytes = applier.stats().history_bytes;
        compute::Contourer contourer(model);
        contourer.update(model);
        const auto t2 = Clock::now();
        row.replay_s = std::chrono::duration<double>(t1 - t0).count();
        row.contour_s = std::chrono::duration<double>(t2 - t1).count();
        time_snapshot_join(model, applier, o.out, row);
        const double now_bytes = static_cast<double>(row.model_bytes + row.packed_history_bytes);
        std::printf("%8.0f %10llu | %10.1f %10.2f %10.2f %12.1f | %10.2f %10.2f %10.3f %10.3f %12.2f\n", minutes,
                    static_cast<unsigned long long>(row.samples), row.bytes / 1e6, row.replay_s, row.contour_s,
                    row.bytes / 10e6 + row.replay_s + row.contour_s, row.model_bytes / 1e6,
                    row.packed_history_bytes / 1e6, row.snapshot_s, row.join_load_s,
                    row.snapshot_s + now_bytes / 10e6 + row.join_load_s);
        js.push_back({{"minutes", minutes}, {"samples", row.samples}, {"bytes", row.bytes}, {"replay_s", row.replay_s},
                      {"contour_s", row.contour_s}, {"model_bytes", row.model_bytes}, {"history_bytes", row.history_bytes},
                      {"packed_history_bytes", row.packed_history_bytes}, {"snapshot_s", row.snapshot_s},
                      {"join_load_s", row.join_load_s}});
        rows.push_back(row);
    }
    app::write_json_file((std::filesystem::path(o.out) / "shared_late_join.json").string(), {{"rows", js}});
    return rows;
}

}  // namespace tridex::bench
