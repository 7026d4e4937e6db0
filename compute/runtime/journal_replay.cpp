// compute/runtime/journal_replay.cpp - a journal's batches and marks through the CPU reference Booleans and the sculpt
// thread's history (compute/journal/journal_replay.hpp declares it: journal/ sits below runtime/).
#include "compute/journal/journal_replay.hpp"

#include <algorithm>
#include <vector>

#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "core/error.hpp"

namespace tridex::compute {

namespace {
Error at(std::uint64_t record, const std::string& what) { return Error("journal record " + std::to_string(record) + ": " + what); }
}  // namespace

std::uint64_t journal_last_serial(std::span<const JournalRecord> records, std::size_t end) {
    std::uint64_t serial = 0;
    for (std::size_t i = 0; i < std::min(end, records.size()); ++i)
        if (records[i].kind == JournalKind::kStrokeEnd) serial = std::max(serial, records[i].serial);
    return serial;
}

JournalApplyStats journal_apply(TriDexel& model, std::span<const JournalRecord> records, const JournalApplyFrom& from) {
    JournalApplyStats st;
    const std::unique_ptr<app::BooleanBackend> cpu = app::make_cpu_backend(model);
    app::SculptHistory history(model, *cpu, from.history_budget_bytes, from.last_serial);
    history.remove_islands(from.remove_islands);
    std::vector<Sweep> batch;
    ToolSample prev{};
    bool have_prev = false;
    // The first sweep after a checkpoint starts at the last sample before it.
    for (std::size_t k = std::min(from.record, records.size()); k-- > 0 && !have_prev;) {
        if (records[k].kind == JournalKind::kBatch && !records[k].samples.empty()) {
            prev = records[k].samples.back();
            have_prev = true;
        }
    }
    bool damaged = false;     // a gap in the record indices lies before record k: marks are matched leniently
    std::int64_t shift = 0;   // journal serial - replay serial, relearnt at each stroke end after a gap
    for (std::size_t k = from.record; k < records.size(); ++k) {
        const JournalRecord& r = records[k];
        if (r.index != (k == 0 ? 0 : records[k - 1].index + 1)) damaged = true;
        switch (r.kind) {
            case JournalKind::kCheckpoint:
                break;
            case JournalKind::kStrokeEnd: {
                const std::uint64_t serial = history.end_stroke();
                if (damaged && serial != r.serial) {
                    if (serial != 0) shift = static_cast<std::int64_t>(r.serial) - static_cast<std::int64_t>(serial);
                    else ++st.marks_skipped;
                    if (serial != 0) ++st.strokes;
                    break;
                }
                if (serial != r.serial)
                    throw at(k, "the journal closes stroke " + std::to_string(r.serial) + " where the replay " +
                                    (serial == 0 ? std::string("has no stroke open") : "closes stroke " + std::to_string(serial)));
                ++st.strokes;
                break;
            }
            case JournalKind::kUndo:
            case JournalKind::kRedo: {
                const bool undo = r.kind == JournalKind::kUndo;
                history.end_stroke();
                const std::uint64_t next = undo ? history.next_undo_serial() : history.next_redo_serial();
                if (damaged) {
                    if (next == 0 || static_cast<std::int64_t>(next) + shift != static_cast<std::int64_t>(r.serial)) {
                        ++st.marks_skipped;
                        break;
                    }
                    (void)(undo ? history.undo() : history.redo());
                    ++(undo ? st.undos : st.redos);
                    break;
                }
                if (next != r.serial)
                    throw at(k, std::string(undo ? "undo" : "redo") + " of stroke " + std::to_string(r.serial) +
                                    ", but the replay's next is " + (next == 0 ? std::string("none") : "stroke " + std::to_string(next)));
                const UndoHistory::Change c = undo ? history.undo() : history.redo();
                if (c.rays != r.rays)
                    throw at(k, std::string(undo ? "undo" : "redo") + " of stroke " + std::to_string(r.serial) + " wrote " +
                                    std::to_string(c.rays) + " rays back, the journal says " + std::to_string(r.rays));
                ++(undo ? st.undos : st.redos);
                break;
            }
            case JournalKind::kBatch: {
                batch.clear();
                for (const ToolSample& s : r.samples) {
                    if (s.tool.kind == ToolKind::kMesh && s.op != ToolOp::kNone)
                        throw at(k, "a mesh tool, which sessions do not have");
                    Sweep sw;
                    if (have_prev && sample_sweep(prev, s, nullptr, sw)) batch.push_back(std::move(sw));
                    prev = s;
                    have_prev = true;
                    st.last_t_s = s.t_s;
                }
                st.samples += r.samples.size();
                if (!batch.empty()) {
                    try {
                        history.apply(batch);
                    } catch (const Error& e) {
                        throw at(k, e.what());
                    }
                    st.booleans += batch.size();
                }
                break;
            }
        }
        ++st.records;
    }
    history.flush();  // a push group the journal's last batch left open (a session that ended without closing it)
    st.islands_removed = history.islands().specks;
    st.island_volume_m3 = history.islands().volume_m3;
    return st;
}

}  // namespace tridex::compute
