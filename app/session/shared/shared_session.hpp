// app/session/shared/shared_session.hpp - `tridex run --host` and `tridex run --join`: a run session with a shared
// session's host or joiner beside it, over ENet sealed with the session's key. docs/shared.md.
#pragma once

#include <vector>

#include "app/session/run/run_session.hpp"
#include "app/session/runtime/session_companion.hpp"

namespace tridex::app {

/// True when the options ask for a shared session (--host or --join).
bool shared_session_asked(const RunOptions& options);

/// Runs the shared session the options ask for: with --host, this session is the host and listens on
/// [ADDR:]PORT for joiners; with --join HOST:PORT, it joins that host (its workpiece is the host's starting model,
/// written to OUT/shared_start.tdx) and follows it until the host ends the session. Either needs the session's key
/// (--shared-key-file or --shared-passphrase-env). Throws tridex::Error on bad options, a port that cannot be bound,
/// a host that cannot be reached or refuses the join, and as RunPipeline::run; CompanionError when a joiner's
/// host went away or its model stopped matching the host's (the session kept its work). `also`: further companions
/// beside it (a cluster wall's ClusterRoot when this site is a wall: run_cluster_session runs this on rank 0).
RunResult run_shared_session(const RunOptions& options, std::vector<SessionCompanion*> also = {});

}  // namespace tridex::app
