// app/session/shared/shared_session.cpp - a run session as a shared session's host or joiner.
#include "app/session/shared/shared_session.hpp"

#include <cstdio>

#include "app/session/run/run_pipeline.hpp"
#include "app/session/shared/shared_host.hpp"
#include "app/session/shared/shared_join.hpp"
#include "app/session/shared/shared_site.hpp"
#include "core/error.hpp"
#include "devices/net/enet_hub.hpp"
#include "devices/net/enet_link.hpp"

namespace tridex::app {

namespace net = devices::net;

namespace {

// How long a silent peer is kept before it counts as gone, s: a loaded machine or a congested link may pause a few
// seconds (ENet's own default is 5 s to 30 s).
constexpr double kPeerTimeoutS = 5.0;

net::SessionKey session_key(const RunOptions& o, const char* what) {
    net::KeySettings k;
    k.key_file = o.shared_key_file;
    k.passphrase_env = o.shared_passphrase_env;
    k.key_file_name = "--shared-key-file";
    k.passphrase_env_name = "--shared-passphrase-env";
    const std::optional<net::SessionKey> key = net::key_from_settings(k);
    if (!key)
        throw Error(std::string(what) + ": a shared session is sealed with the session's key: give --shared-key-file "
                    "FILE (32 bytes, or 64 hex digits) or --shared-passphrase-env VAR (docs/shared.md)");
    return *key;
}

Vec3 colour_of_site_name(const std::string& name) {
    // A stable colour per name, so each person keeps theirs from session to session.
    std::uint32_t h = 2166136261u;
    for (const char c : name) h = (h ^ static_cast<unsigned char>(c)) * 16777619u;
    const double hue = (h % 360u) / 60.0;
    const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
    const int i = static_cast<int>(hue);
    const Vec3 rgb = i == 0 ? Vec3(1, x, 0) : i == 1 ? Vec3(x, 1, 0) : i == 2 ? Vec3(0, 1, x)
                   : i == 3 ? Vec3(0, x, 1) : i == 4 ? Vec3(x, 0, 1) : Vec3(1, 0, x);
    return 0.25 + 0.7 * rgb;
}

RunResult run_host(const RunOptions& options, std::vector<SessionCompanion*> also) {
    std::string host;
    std::uint16_t port = 0;
    net::split_listen_address(options.host, "--host", host, port);  // port 0: one the system picks, which the line names
    SharedHostOptions ho;
    ho.key = session_key(options, "--host");
    ho.name = options.site_name.empty() ? "host" : options.site_name;
    ho.colour = colour_of_site_name(ho.name);
    ho.out = options.out;
    std::shared_ptr<net::EnetHub> hub = net::EnetHub::listen(host, port, kMaxSites - 1, kPeerTimeoutS);
    std::fprintf(stderr, "tridex: hosting a shared session on %s; others join with: tridex run --join THIS_HOST:%u "
                         "--shared-key-file ... (or --shared-passphrase-env ...)\n",
                 hub->where(), static_cast<unsigned>(hub->port()));
    SharedHost shared(ho, [hub] { return hub->accept(); });
    SharedHostSite site(shared);
    also.insert(also.begin(), &site);
    return RunPipeline(options, also).run();
}

RunResult run_joiner(const RunOptions& options, std::vector<SessionCompanion*> also) {
    if (!options.workpiece.empty() || !options.mesh.empty())
        throw Error("--join: the workpiece is the host's; leave out --workpiece and --mesh");
    std::string host;
    std::uint16_t port = 0;
    net::split_host_port(options.join, "--join", host, port);
    SharedJoinOptions jo;
    jo.name = options.site_name.empty() ? "guest" : options.site_name;
    jo.colour = colour_of_site_name(jo.name);
    jo.out = options.out;
    jo.from_start = !options.cluster.empty();  // a wall's render ranks replay the stream from the session's start
    const net::SessionKey key = session_key(options, "--join");
    (void)resolve_run(options);  // this site's own scene and options are checked before it takes a site at the host
    SharedJoin shared(jo, net::EnetLink::connect(host, port, kPeerTimeoutS), key);
    const SharedJoin::Joined joined = shared.join();
    const SessionSpec host_spec = spec_from_json(joined.welcome.spec_json, "--join " + options.join + ": the host's session");
    std::fprintf(stderr, "tridex: joined %s's shared session at %s as site %d\n", joined.welcome.host_name.c_str(),
                 options.join.c_str(), joined.welcome.site);
    RunOptions o = options;
    o.workpiece = joined.start_path;
    o.keep_islands = host_spec.keep_islands;
    o.history_mib = static_cast<double>(host_spec.history_budget_bytes) / 1048576.0;
    SharedJoinSite site(shared);
    also.insert(also.begin(), &site);
    return RunPipeline(o, also).run();
}

}  // namespace

bool shared_session_asked(const RunOptions& options) { return !options.host.empty() || !options.join.empty(); }

RunResult run_shared_session(const RunOptions& options, std::vector<SessionCompanion*> also) {
    if (!options.host.empty() && !options.join.empty()) throw Error("--host and --join: choose one");
    return options.host.empty() ? run_joiner(options, std::move(also)) : run_host(options, std::move(also));
}

}  // namespace tridex::app
