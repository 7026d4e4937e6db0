// app/session/shared/shared_site.hpp - a run session's side of a shared session: the companions that tie a
// SharedHost or a SharedJoin to the session's threads, frames and report. docs/shared.md.
#pragma once

#include <string>
#include <vector>

#include "app/session/runtime/session_companion.hpp"
#include "app/session/shared/shared_host.hpp"
#include "app/session/shared/shared_join.hpp"

namespace tridex::app {

/// Writes the session's starting model to `<out>/shared_start.tdx` (the host's options.out) and starts `host` with
/// its bytes, the model and the spec; late joiners get the model as it stands, written the same way to
/// `<out>/shared_late_join.tdx`. Throws tridex::Error when the file cannot be written or read back, or as
/// SharedHost::start.
void start_shared_host(SharedHost& host, const Workpiece& workpiece, const SessionSpec& spec);

/// Refuses to follow the host when this site's spec (`here`) would build another model from the same stream than
/// the host's (`host_spec_json`, the welcome's): its clay grouping, islands or undo memory. Throws tridex::Error
/// "--join HOST: ..." naming the setting.
void check_joiner_spec(const SessionSpec& here, const std::string& host_spec_json, const std::string& host);

/// The host's companion: the sculpt thread streams to the host, the starting model goes to it when the threads
/// are made, this site's tool to the joiners each frame, and the host's report to report.json `shared`.
class SharedHostSite final : public SessionCompanion {
public:
    /// `host` must outlive the session.
    explicit SharedHostSite(SharedHost& host) : host_(host) {}
    void configure(SculptOptions& options) override { host_.configure(options); }
    void starting(SessionRuntime& runtime) override;
    void before_present(const FrameShown& shown) override;
    void stopped(SessionRuntime& runtime, const FrameShown& last) override;
    /// The joiners heard from and not gone.
    void add_presence(std::vector<SitePresence>& out) const override;
    nlohmann::json report() const override { return host_.report(); }
    std::string report_key() const override { return "shared"; }

private:
    SharedHost& host_;
};

/// A joiner's companion: the sculpt thread follows the host, the session's spec is checked against the host's when
/// the threads are made, this site's tool goes to the host each frame, the session ends when the host ends it and
/// fails when the host goes away or the replica stops matching.
class SharedJoinSite final : public SessionCompanion {
public:
    /// `join` (joined already) must outlive the session.
    explicit SharedJoinSite(SharedJoin& join) : join_(join) {}
    void configure(SculptOptions& options) override { join_.configure(options); }
    void starting(SessionRuntime& runtime) override;
    void before_present(const FrameShown& shown) override;
    void stopped(SessionRuntime& runtime, const FrameShown& last) override;
    /// The other sites heard from and not gone.
    void add_presence(std::vector<SitePresence>& out) const override;
    std::string failure() const override { return join_.failure(); }
    std::string ended() const override { return join_.ended(); }
    bool holds_session_open() const override { return true; }
    nlohmann::json report() const override { return join_.report(); }
    std::string report_key() const override { return "shared"; }

private:
    SharedJoin& join_;
};

}  // namespace tridex::app
