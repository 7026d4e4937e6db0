// app/session/cluster/cluster_session.hpp - `tridex run SCENE --cluster CONFIG` under mpirun: rank 0 runs the session,
// the other ranks draw the wall's viewports.
#pragma once

#include <functional>
#include <vector>

#include "app/session/run/run_session.hpp"
#include "app/session/runtime/session_companion.hpp"

namespace tridex::app {

/// What one rank of a cluster session did.
struct ClusterRunResult {
    int rank = 0;                    ///< this process's rank
    std::optional<RunResult> run;    ///< rank 0: the session (as run_stereo_session's)
    int exit_code = 0;               ///< 0 = ended normally
};

/// How rank 0 runs its session with the companions given (the ClusterRoot among them): a plain run session
/// (RunPipeline), or a shared session's host or joiner (run_shared_session), which adds its own.
using RankZeroRun = std::function<RunResult(const RunOptions& options, std::vector<SessionCompanion*> companions)>;

/// Runs this process's part of the cluster session of `options` (options.cluster names the config): rank 0 runs
/// the session with a ClusterRoot beside it, through `rank_zero` (empty: RunPipeline); every other rank runs its
/// viewports (run_render_rank). Under mpirun the ranks are MPI's; with options.cluster_listen (rank 0) or
/// options.cluster_connect and cluster_rank (a render rank) they are processes started by hand that reach each other
/// over the network (app/session/cluster/net_transport.hpp), and render ranks may join the running wall or take a
/// failed one's place. Throws tridex::Error for a bad --cluster-listen, --cluster-connect or --rank, and (without
/// them) when this build has no MPI, the process was not started by mpirun, the config is bad or names
/// another number of ranks, or (rank 0) as run_stereo_session; a rank 0 whose render rank failed writes all its
/// outputs first, then throws naming the rank. The caller then ends every rank (ClusterTransport::abort_all via
/// end_cluster_session).
ClusterRunResult run_cluster_session(const RunOptions& options, const RankZeroRun& rank_zero = {});

/// Ends every rank of the running cluster session with `code` after rank 0 failed (MPI_Abort); returns when there
/// is no cluster session in this process.
void end_cluster_session(int code);

}  // namespace tridex::app
