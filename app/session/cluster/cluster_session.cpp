// app/session/cluster/cluster_session.cpp - the ranks of a cluster session and their roles.
#include "app/session/cluster/cluster_session.hpp"

#include <cstdlib>
#include <memory>

#include "app/session/cluster/cluster_config.hpp"
#include "app/session/cluster/cluster_root.hpp"
#include "app/session/cluster/cluster_transport.hpp"
#include "app/session/cluster/render_rank.hpp"
#include "app/session/run/run_pipeline.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {

// The session's transport, kept so that end_cluster_session can reach every rank after rank 0 failed.
std::unique_ptr<ClusterTransport>& transport_slot() {
    static std::unique_ptr<ClusterTransport> t;
    return t;
}

}  // namespace

bool launched_by_mpirun() {
    return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMIX_RANK") != nullptr ||
           std::getenv("PMI_RANK") != nullptr;
}

ClusterRunResult run_cluster_session(const RunOptions& options, const RankZeroRun& rank_zero) {
    if (!cluster_supported()) (void)make_mpi_transport();  // throws the reason
    if (!launched_by_mpirun())
        throw Error("--cluster " + options.cluster + ": a cluster session is started by mpirun, one rank per machine "
                    "and rank 0 running the session: mpirun -np K+1 tridex run ... --cluster CONFIG, for a config "
                    "naming K render ranks (docs/wall.md)");
    const RunSetup setup = resolve_run(options);  // the wall's display config, and the options checked on every rank
    const ClusterConfig config = read_cluster_config(options.cluster, setup.scene.display);
    transport_slot() = make_mpi_transport();
    ClusterTransport& t = *transport_slot();
    ClusterRunResult out;
    out.rank = t.rank();
    if (t.size() != static_cast<int>(config.ranks.size()) + 1)
        throw Error(config.source + ": names " + std::to_string(config.ranks.size()) + " render ranks, so the session needs mpirun -np " +
                    std::to_string(config.ranks.size() + 1) + "; it was started with " + std::to_string(t.size()) + " ranks");
    if (t.rank() != 0) {
        RenderRankOptions ro;
        ro.out = setup.out;
        ro.validate = setup.validate;
        out.exit_code = run_render_rank(t, config, ro);
        if (out.exit_code == 0) transport_slot().reset();  // MPI_Finalize
        return out;
    }
    ClusterRoot root(t, config);
    out.run = rank_zero ? rank_zero(options, {&root}) : RunPipeline(options, {&root}).run();
    transport_slot().reset();
    return out;
}

void end_cluster_session(int code) {
    if (transport_slot()) transport_slot()->abort_all(code);
}

}  // namespace tridex::app
