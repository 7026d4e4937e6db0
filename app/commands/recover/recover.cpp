// app/commands/recover/recover.cpp - `tridex recover`: a session's model from its journal.
#include "app/commands/recover/recover.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "app/support/json_file.hpp"
#include "app/support/memory.hpp"
#include "app/support/output_dir.hpp"
#include "app/support/progress.hpp"
#include "app/scene/workpiece_list.hpp"
#include "app/scene/workpiece_source.hpp"
#include "app/session/record/session_recording.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "app/scene/session_spec.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/mesh/mesh_export.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/model/volume.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace fs = std::filesystem;

namespace {

// What the reader skipped, summed; one stderr line per damaged stretch, one for a tail left out after damage and one
// for a cut end.
struct DamageTotals {
    std::uint64_t records = 0, bytes = 0, samples = 0;
};

DamageTotals report_damage(const std::string& journal_path, const compute::Journal& j) {
    DamageTotals t;
    for (const compute::JournalDamage& d : j.damage) {
        t.records += d.records_lost;
        t.bytes += d.bytes;
        t.samples += d.samples_lost;
        std::fprintf(stderr,
                     "tridex: %s: skipped %llu damaged record%s (%llu bytes at offset %llu; about %llu samples): %s; "
                     "resumed at the next intact one\n",
                     journal_path.c_str(), static_cast<unsigned long long>(d.records_lost),
                     d.records_lost == 1 ? "" : "s",
                     static_cast<unsigned long long>(d.bytes), static_cast<unsigned long long>(d.byte_offset),
                     static_cast<unsigned long long>(d.samples_lost), d.reason.c_str());
    }
    if (j.tail_unplaced > 0)
        std::fprintf(stderr,
                     "tridex: %s: about %llu samples received after the last applied batch are not replayed: the "
                     "damage before them leaves their place in the stream unknown\n",
                     journal_path.c_str(), static_cast<unsigned long long>(j.tail_unplaced));
    if (j.cut)
        std::fprintf(stderr, "tridex: %s: cut at record %llu (byte offset %llu): %s; recovering the records before it\n",
                     journal_path.c_str(), static_cast<unsigned long long>(j.cut->record),
                     static_cast<unsigned long long>(j.cut->byte_offset), j.cut->reason.c_str());
    return t;
}

}  // namespace

void run_recover(const std::string& journal_path, const std::string& out) {
    const auto t0 = std::chrono::steady_clock::now();
    prepare_output_dir(out, "--out");
    compute::Journal j = compute::read_journal(journal_path);
    SessionSpec s = spec_from_json(j.session, journal_path);
    // The samples hold what the hand did, reference objects' pushes included: the model needs none of their meshes.
    s.references.clear();
    check_inputs_unchanged(s, journal_path, "the session");
    validate_spec(s, journal_path);
    // A sample with a tool no session of this spec uses is damage as much as a CRC mismatch: cut there.
    for (std::size_t k = 0; k < j.records.size(); ++k) {
        std::string bad;
        for (std::size_t i = 0; i < j.records[k].samples.size() && bad.empty(); ++i) {
            bad = recorded_tool_problem(s.tool, j.records[k].samples[i].tool);
            if (!bad.empty()) bad = "sample " + std::to_string(i) + ": " + bad;
        }
        if (bad.empty()) continue;
        j.cut = compute::JournalCut{k, j.records[k].offset, bad};
        j.records.resize(k);
        break;
    }
    {
        std::vector<NamedFile> inputs = {{"the journal", journal_path}, {"the session's workpiece model", s.model_path}};
        for (const compute::JournalRecord& rec : j.records)
            if (rec.kind == compute::JournalKind::kCheckpoint)
                inputs.push_back({"a checkpoint of the journal",
                                  (fs::path(journal_path).parent_path() / rec.checkpoint).string()});
        check_distinct_files({{"--out's sculpted.ply", (fs::path(out) / "sculpted.ply").string()},
                              {"--out's model.tdx", (fs::path(out) / "model.tdx").string()},
                              {"--out's report.json", (fs::path(out) / "report.json").string()}},
                             inputs);
    }
    const DamageTotals damage = report_damage(journal_path, j);

    // The workpiece as the session built it; then the records after the newest checkpoint that is intact and
    // replays, else every record from the start.
    Workpiece wp = prepare_session_workpiece(s);
    const double volume_start = wp.volume_dexel_m3;
    compute::JournalApplyStats applied;
    std::string from = "the start";
    bool done = false;
    for (std::size_t k = j.records.size(); k-- > 0 && !done;) {
        const compute::JournalRecord& rec = j.records[k];
        if (rec.kind != compute::JournalKind::kCheckpoint) continue;
        const std::string path = (fs::path(journal_path).parent_path() / rec.checkpoint).string();
        try {
            const auto [crc, bytes] = file_crc32(path);
            if (crc != rec.checkpoint_crc || bytes != rec.checkpoint_bytes)
                throw Error(path + ": not the checkpoint the journal names (another size or CRC-32)");
            compute::TdxModel m = compute::load_tdx(path, model_memory_budget_bytes());
            if (m.model.lattice.cells != wp.model.lattice.cells || m.model.lattice.cell_m != wp.model.lattice.cell_m ||
                m.model.lattice.origin_m != wp.model.lattice.origin_m)
                throw Error(path + ": its lattice is not the session's");
            compute::TriDexel model = std::move(m.model);
            std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), std::uint8_t{1});  // contoured whole below
            compute::JournalApplyFrom start = replay_settings(s);
            start.record = k + 1;
            start.last_serial = compute::journal_last_serial(j.records, k);
            ProgressReporter::Step step =
                progress().step("replaying " + std::to_string(j.records.size() - k - 1) + " journal records");
            applied = compute::journal_apply(model, j.records, start, step.fn());
            applied.records += k + 1;  // the records the checkpoint holds
            wp.model = std::move(model);
            from = "checkpoint " + rec.checkpoint + " (record " + std::to_string(k) + ")";
            done = true;
        } catch (const Error& e) {
            std::fprintf(stderr, "tridex: %s: checkpoint at record %zu not used: %s\n", journal_path.c_str(), k, e.what());
        }
    }
    if (!done) {
        const compute::JournalApplyFrom start = replay_settings(s);
        try {
            ProgressReporter::Step step =
                progress().step("replaying " + std::to_string(j.records.size()) + " journal records");
            applied = compute::journal_apply(wp.model, j.records, start, step.fn());
        } catch (const Error& e) {
            throw Error(journal_path + ": " + e.what());
        }
    }
    compute::Contourer contourer(wp.model);
    TriMesh mesh;
    {
        ProgressReporter::Step step = progress().step("contouring the model");
        contourer.update(wp.model, step.fn());
        mesh = contourer.mesh();
    }
    const fs::path dir(out);
    compute::write_ply((dir / "sculpted.ply").string(), mesh, contourer.mesh_materials());
    save_session_model((dir / "model.tdx").string(), wp, s);  // a later session starts from it (--workpiece)

    const double after = compute::dexel_volume_m3(wp.model);
    nlohmann::json r;
    r["journal"] = journal_path;
    r["journal_version"] = j.version;
    r["settings"] = nlohmann::json::parse(spec_to_json(s));
    r["recovered_device_time_s"] = applied.last_t_s;
    r["records"] = applied.records;
    r["samples"] = applied.samples;
    r["tail_samples"] = applied.tail_samples;
    r["booleans"] = applied.booleans;
    r["strokes"] = applied.strokes;
    r["undos"] = applied.undos;
    r["redos"] = applied.redos;
    r["islands_removed"] = applied.islands_removed;
    r["island_volume_m3"] = applied.island_volume_m3;
    r["replayed_from"] = from;
    r["volume_dexel_m3"] = volume_start;
    r["volume_after_m3"] = after;
    r["volume_removed_m3"] = volume_start - after;
    r["truncated_at"] = j.cut ? nlohmann::json{{"record", j.cut->record},
                                               {"byte_offset", j.cut->byte_offset},
                                               {"reason", j.cut->reason}}
                              : nlohmann::json(nullptr);
    r["journal_damage"] = {{"damaged_records", damage.records},
                           {"skipped_bytes", damage.bytes},
                           {"samples_lost", damage.samples},
                           {"marks_skipped", applied.marks_skipped},
                           {"tail_samples_unplaced", j.tail_unplaced}};
    r["mesh"] = {{"vertices", mesh.positions.size()}, {"triangles", mesh.triangles.size()}};
    r["files"] = {(dir / "sculpted.ply").string(), (dir / "model.tdx").string(), (dir / "report.json").string()};
    r["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    write_json_file((dir / "report.json").string(), r);
    // From a checkpoint, the samples are only those replayed after it; the records count the whole journal.
    const std::string start_from = done ? from + ", then " : "from the start, ";
    if (applied.marks_skipped > 0)
        std::fprintf(stderr, "tridex: %s: %llu stroke marks after the damage no longer matched the replay and were skipped\n",
                     journal_path.c_str(), static_cast<unsigned long long>(applied.marks_skipped));
    const std::string tail = applied.tail_samples > 0 ? ", " + std::to_string(applied.tail_samples) +
                                                            " of them received by the session but not yet applied"
                                                      : std::string();
    std::printf("recovered %llu records (%s%llu samples replayed%s, to %.3f s of device time) from %s into %s\n",
                static_cast<unsigned long long>(applied.records), start_from.c_str(),
                static_cast<unsigned long long>(applied.samples), tail.c_str(), applied.last_t_s, journal_path.c_str(),
                out.c_str());
    std::printf("  wrote %s/: sculpted.ply, model.tdx, report.json (`tridex run --workpiece %s` carries on)\n",
                out.c_str(), (dir / "model.tdx").string().c_str());
    for (std::size_t k = 1; k <= s.more_workpieces.size(); ++k)  // each further workpiece kept its own journal
        std::printf("  the session's workpiece %zu has its own journal: tridex recover %s\n", k + 1,
                    path_for_workpiece(journal_path, k).c_str());
}

}  // namespace tridex::app
