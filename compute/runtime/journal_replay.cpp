// compute/runtime/journal_replay.cpp - a journal's batches and marks through the CPU reference Booleans and the sculpt
// thread's history (compute/journal/journal_replay.hpp declares it: journal/ sits below runtime/).
#include "compute/journal/journal_replay.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <optional>
#include <vector>

#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "compute/tools/site_sweeps.hpp"
#include "core/error.hpp"

namespace tridex::compute {

namespace {
Error at(std::uint64_t record, const std::string& what) { return Error("journal record " + std::to_string(record) + ": " + what); }
}  // namespace

std::vector<ToolSample> journal_last_samples(std::span<const JournalRecord> records, std::size_t end) {
    std::array<const ToolSample*, kMaxSites> last{};
    for (std::size_t k = 0; k < std::min(end, records.size()); ++k)
        if (records[k].kind == JournalKind::kBatch)
            for (const ToolSample& s : records[k].samples)
                if (s.site < kMaxSites) last[s.site] = &s;
    std::vector<ToolSample> out;
    for (const ToolSample* s : last)
        if (s) out.push_back(*s);
    return out;
}

std::uint64_t journal_last_serial(std::span<const JournalRecord> records, std::size_t end) {
    std::uint64_t serial = 0;
    for (std::size_t i = 0; i < std::min(end, records.size()); ++i)
        if (records[i].kind == JournalKind::kStrokeEnd || records[i].kind == JournalKind::kLattice)
            serial = std::max(serial, records[i].serial);
    return serial;
}

struct JournalApplier::State {
    std::unique_ptr<app::BooleanBackend> cpu;
    app::SculptHistory history;
    std::vector<Sweep> batch;
    TriDexel& model;  // its lattice's centre is the symmetry centre (a lattice record changes the lattice)
    SiteSweeps sites;  // each site's previous sample, and whose stroke is open
    std::optional<std::uint64_t> last_index;  // index of the last record seen (none: the next is the journal's first)
    std::uint64_t position = 0;               // records seen, for error messages
    bool damaged = false;    // a gap in the record indices lay before: marks are matched leniently
    std::int64_t shift = 0;  // journal serial - replay serial, relearnt at each stroke end after a gap
    JournalApplyStats st;

    State(TriDexel& model, const JournalApplyFrom& from)
        : cpu(app::make_cpu_backend(model)),
          history(model, *cpu, from.history_budget_bytes, from.last_serial),
          model(model) {
        history.remove_islands(from.remove_islands);
        cpu->set_clay_group_sweeps(from.clay_group_sweeps);
    }

    // Closes the open stroke as the sculpt thread does (SculptThread::close_stroke): the samples left unswept within
    // the sweep spacing are swept into it first.
    std::uint64_t end_stroke(std::uint64_t k) {
        try {
            sites.finish_strokes(symmetry_centre(model.lattice), batch);
        } catch (const Error& e) {
            throw at(k, e.what());
        }
        apply_batch(k);
        return history.end_stroke();
    }

    void stroke_end(std::uint64_t k, const JournalRecord& r) {
        const std::uint64_t serial = end_stroke(k);
        if (damaged && serial != r.serial) {
            if (serial != 0) shift = static_cast<std::int64_t>(r.serial) - static_cast<std::int64_t>(serial);
            else ++st.marks_skipped;
            if (serial != 0) ++st.strokes;
            return;
        }
        if (serial != r.serial)
            throw at(k, "the journal closes stroke " + std::to_string(r.serial) + " where the replay " +
                            (serial == 0 ? std::string("has no stroke open") : "closes stroke " + std::to_string(serial)));
        ++st.strokes;
    }

    void undo_redo(std::uint64_t k, const JournalRecord& r) {
        const bool undo = r.kind == JournalKind::kUndo;
        end_stroke(k);
        const std::uint64_t next = undo ? history.next_undo_serial() : history.next_redo_serial();
        if (damaged) {
            if (next == 0 || static_cast<std::int64_t>(next) + shift != static_cast<std::int64_t>(r.serial)) {
                ++st.marks_skipped;
                return;
            }
            (void)(undo ? history.undo() : history.redo());
            ++(undo ? st.undos : st.redos);
            return;
        }
        if (next != r.serial)
            throw at(k, std::string(undo ? "undo" : "redo") + " of stroke " + std::to_string(r.serial) +
                            ", but the replay's next is " + (next == 0 ? std::string("none") : "stroke " + std::to_string(next)));
        const UndoHistory::Change c = undo ? history.undo() : history.redo();
        if (c.rays != r.rays)
            throw at(k, std::string(undo ? "undo" : "redo") + " of stroke " + std::to_string(r.serial) + " wrote " +
                            std::to_string(c.rays) + " rays back, the journal says " + std::to_string(r.rays));
        ++(undo ? st.undos : st.redos);
    }

    // The model re-sampled (its coarseness changed) as one undo step, after the open stroke closed.
    void lattice(std::uint64_t k, const JournalRecord& r) {
        end_stroke(k);
        if (r.rays < static_cast<std::uint64_t>(kResampleMinResolution) ||
            r.rays > static_cast<std::uint64_t>(kResampleMaxResolution))
            throw at(k, "a coarseness change to resolution " + std::to_string(r.rays) + ", outside " +
                            std::to_string(kResampleMinResolution) + ".." + std::to_string(kResampleMaxResolution));
        UndoHistory::Change c;
        try {
            c = history.resample(static_cast<int>(r.rays), std::numeric_limits<std::size_t>::max());
        } catch (const Error& e) {
            throw at(k, e.what());
        }
        if (c.serial != r.serial) {
            if (!damaged)
                throw at(k, "the journal changes the coarseness as step " + std::to_string(r.serial) +
                                " where the replay's step is " + std::to_string(c.serial));
            shift = static_cast<std::int64_t>(r.serial) - static_cast<std::int64_t>(c.serial);
        }
        ++st.lattices;
    }

    void sweep_to(std::uint64_t k, const ToolSample& s) {
        if (s.tool.kind == ToolKind::kMesh && s.op != ToolOp::kNone) throw at(k, "a mesh tool, which sessions do not have");
        try {
            sites.advance(s, nullptr, nullptr, symmetry_centre(model.lattice), model.lattice.cell_m, batch);
        } catch (const Error& e) {
            throw at(k, e.what());
        }
        st.last_t_s = s.t_s;
    }

    void apply_batch(std::uint64_t k) {
        if (batch.empty()) return;
        try {
            history.apply(batch);
        } catch (const Error& e) {
            throw at(k, e.what());
        }
        st.booleans += batch.size();
        batch.clear();
    }

    void samples(std::uint64_t k, const JournalRecord& r) {
        batch.clear();
        for (const ToolSample& s : r.samples) sweep_to(k, s);
        st.samples += r.samples.size();
        apply_batch(k);
    }

    // The tail (samples received, never applied): as the sculpt thread applies what it drains, one batch per stroke,
    // a stroke closed where the tool stops cutting or changes.
    void tail(std::uint64_t k, const JournalRecord& r) {
        batch.clear();
        for (const ToolSample& s : r.samples) {
            StrokeClose close = StrokeClose::kNo;
            try {
                close = sites.closes_before(s, history.stroke_open() || !batch.empty());
            } catch (const Error& e) {
                throw at(k, e.what());
            }
            if (close != StrokeClose::kNo) {
                apply_batch(k);
                if (end_stroke(k) != 0) ++st.strokes;
            }
            sweep_to(k, s);
        }
        st.samples += r.samples.size();
        st.tail_samples += r.samples.size();
        apply_batch(k);
    }

    void one(const JournalRecord& r) {
        const std::uint64_t k = position++;
        if (r.index != (last_index ? *last_index + 1 : 0)) damaged = true;
        last_index = r.index;
        switch (r.kind) {
            case JournalKind::kCheckpoint:
            case JournalKind::kIntake: break;
            case JournalKind::kStrokeEnd: stroke_end(k, r); break;
            case JournalKind::kUndo:
            case JournalKind::kRedo: undo_redo(k, r); break;
            case JournalKind::kLattice: lattice(k, r); break;
            case JournalKind::kBatch: r.tail ? tail(k, r) : samples(k, r); break;
        }
        ++st.records;
    }

    void update_islands() {
        st.islands_removed = history.islands().specks;
        st.island_volume_m3 = history.islands().volume_m3;
        st.history_bytes = history.stats().bytes;
    }
};

JournalApplier::JournalApplier(TriDexel& model, const JournalApplyFrom& from) : s_(std::make_unique<State>(model, from)) {}

JournalApplier::~JournalApplier() = default;

void JournalApplier::resume_after(std::uint64_t last_index, std::span<const ToolSample> prevs,
                                  std::uint64_t records_before) {
    s_->last_index = last_index;
    s_->position = records_before;
    for (const ToolSample& p : prevs) s_->sites.set_prev(p);
}

void JournalApplier::load_history(std::span<const unsigned char> steps) { s_->history.load_steps(steps); }

void JournalApplier::apply(std::span<const JournalRecord> records) {
    for (const JournalRecord& r : records) s_->one(r);
    s_->update_islands();
}

void JournalApplier::flush() {
    s_->history.flush();
    s_->update_islands();
}

const JournalApplyStats& JournalApplier::stats() const { return s_->st; }

std::vector<unsigned char> JournalApplier::history_steps() const { return s_->history.save_steps(); }

bool JournalApplier::stroke_open() const { return s_->history.stroke_open() || !s_->batch.empty(); }

JournalApplyStats journal_apply(TriDexel& model, std::span<const JournalRecord> records, const JournalApplyFrom& from,
                                const ProgressFn& progress) {
    JournalApplier applier(model, from);
    const std::size_t first = std::min(from.record, records.size());
    if (first > 0) {
        // Each site's first sweep after a checkpoint starts at its last sample before it.
        applier.resume_after(records[first - 1].index, journal_last_samples(records, first), first);
    }
    const std::span<const JournalRecord> rest = records.subspan(first);
    // Records a few at a time, as JournalApplier allows, so that progress can be told between them.
    constexpr std::size_t kSlices = 100;
    const std::size_t per_slice =
        progress ? std::max<std::size_t>(1, (rest.size() + kSlices - 1) / kSlices) : rest.size();
    for (std::size_t k = 0; k < rest.size(); k += per_slice) {
        const std::size_t n = std::min(per_slice, rest.size() - k);
        applier.apply(rest.subspan(k, n));
        report_progress(progress, static_cast<double>(k + n), static_cast<double>(rest.size()));
    }
    applier.flush();  // a push group the journal's last batch left open (a session that ended without closing it)
    return applier.stats();
}

}  // namespace tridex::compute
