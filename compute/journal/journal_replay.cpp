// compute/journal/journal_replay.cpp - a journal's batches through the CPU reference Booleans.
#include "compute/journal/journal_replay.hpp"

#include <vector>

#include "compute/runtime/boolean_backend.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "core/error.hpp"

namespace tridex::compute {

JournalApplyStats journal_apply(TriDexel& model, std::span<const JournalRecord> records) {
    JournalApplyStats st;
    const std::unique_ptr<app::BooleanBackend> cpu = app::make_cpu_backend(model);
    std::vector<Sweep> batch;
    ToolSample prev{};
    bool have_prev = false;
    for (const JournalRecord& r : records) {
        batch.clear();
        for (const ToolSample& s : r.samples) {
            if (s.tool.kind == ToolKind::kMesh && s.op != ToolOp::kNone)
                throw Error("journal record " + std::to_string(st.records) + ": a mesh tool, which sessions do not have");
            Sweep sw;
            if (have_prev && sample_sweep(prev, s, nullptr, sw)) batch.push_back(std::move(sw));
            prev = s;
            have_prev = true;
            st.last_t_s = s.t_s;
        }
        st.samples += r.samples.size();
        if (!batch.empty()) {
            try {
                cpu->apply(batch);
            } catch (const Error& e) {
                throw Error("journal record " + std::to_string(st.records) + ": " + e.what());
            }
            st.booleans += batch.size();
        }
        ++st.records;
    }
    return st;
}

}  // namespace tridex::compute
