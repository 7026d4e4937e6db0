// app/session/shared/shared_site.cpp - the run session's side of a shared session.
#include "app/session/shared/shared_site.hpp"

#include <filesystem>

#include "app/scene/workpiece_source.hpp"
#include "app/session/view/presence_view.hpp"
#include "app/support/file_bytes.hpp"
#include "compute/model/tdx_file.hpp"
#include "core/error.hpp"

namespace tridex::app {

void start_shared_host(SharedHost& host, const Workpiece& workpiece, const SessionSpec& spec) {
    const std::filesystem::path out(host.options().out);
    const std::string path = (out / "shared_start.tdx").string();
    save_session_model(path, workpiece, spec);
    // A late joiner's model as it stands, saved as this session saves its model (on the host's network thread).
    const std::string late = (out / "shared_late_join.tdx").string();
    host.start(workpiece.model, read_file_bytes(path), spec_to_json(spec),
               [late, to_world = workpiece.to_world, json = spec_to_json(spec), palette = spec.palette](
                   const compute::TriDexel& model) {
                   compute::save_tdx(late, model, to_world, json, 3, palette);
                   return read_file_bytes(late);
               });
}

void check_joiner_spec(const SessionSpec& here, const std::string& host_spec_json, const std::string& host) {
    // What decides the model besides the stream must be the host's, or the replica would drift from it.
    const SessionSpec h = spec_from_json(host_spec_json, "--join " + host + ": the host's session");
    if (here.clay_group_sweeps != h.clay_group_sweeps)
        throw Error("--join " + host + ": this site's scene groups " + std::to_string(here.clay_group_sweeps) +
                    " clay sweeps, the host's " + std::to_string(h.clay_group_sweeps) + "; use the host's setting");
    if (here.keep_islands != h.keep_islands || here.history_budget_bytes < h.history_budget_bytes)
        throw Error("--join " + host + ": this site keeps islands or undo memory unlike the host");
}

namespace {
void add_present(const std::vector<SitePresence>& heard, std::vector<SitePresence>& out) {
    for (const SitePresence& p : heard)
        if (!p.gone) out.push_back(p);
}
}  // namespace

void SharedHostSite::starting(SessionRuntime& runtime) { start_shared_host(host_, runtime.workpiece(), runtime.spec()); }

void SharedHostSite::before_present(const FrameShown& shown) {
    host_.set_own_presence(presence_of(shown, 0, host_.options().name, host_.options().colour));
}

void SharedHostSite::stopped(SessionRuntime& runtime, const FrameShown&) { host_.finish(runtime.workpiece().model); }

void SharedHostSite::add_presence(std::vector<SitePresence>& out) const { add_present(host_.others(), out); }

void SharedJoinSite::starting(SessionRuntime& runtime) {
    check_joiner_spec(runtime.spec(), join_.welcome().spec_json, join_.host());
}

void SharedJoinSite::before_present(const FrameShown& shown) {
    join_.set_own_presence(presence_of(shown, join_.welcome().site, join_.options().name, join_.options().colour));
}

void SharedJoinSite::stopped(SessionRuntime& runtime, const FrameShown&) { join_.finish(runtime.workpiece().model); }

void SharedJoinSite::add_presence(std::vector<SitePresence>& out) const { add_present(join_.others(), out); }

}  // namespace tridex::app
