// app/session/cluster/cluster_session.cpp - the ranks of a cluster session and their roles.
#include "app/session/cluster/cluster_session.hpp"

#include <cstdio>
#include <cstdlib>
#include <memory>

#include "app/session/cluster/cluster_config.hpp"
#include "app/session/cluster/cluster_root.hpp"
#include "app/session/cluster/cluster_transport.hpp"
#include "app/session/cluster/net_transport.hpp"
#include "app/session/cluster/render_rank.hpp"
#include "app/session/run/run_pipeline.hpp"
#include "core/error.hpp"
#include "devices/net/enet_link.hpp"

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

namespace {

// The key that seals a network wall's link: the config's, or none.
std::optional<devices::net::SessionKey> wall_key(const ClusterConfig& config) {
    devices::net::KeySettings k;
    k.key_file = config.key_file;
    k.passphrase_env = config.passphrase_env;
    k.key_file_name = config.source + ": key_file";
    k.passphrase_env_name = config.source + ": passphrase_env";
    return devices::net::key_from_settings(k);
}

// This process's part once transport_slot() holds its transport: a render rank's viewports, or rank 0's session with
// a ClusterRoot beside it. A render rank that failed keeps its transport, so that end_cluster_session still reaches
// every rank.
ClusterRunResult run_this_rank(const RunOptions& options, const RankZeroRun& rank_zero, const RunSetup& setup,
                               const ClusterConfig& config) {
    ClusterTransport& t = *transport_slot();
    ClusterRunResult out;
    out.rank = t.rank();
    if (t.rank() != 0) {
        RenderRankOptions ro;
        ro.out = setup.out;
        ro.validate = setup.validate;
        out.exit_code = run_render_rank(t, config, ro);
        if (out.exit_code == 0) transport_slot().reset();  // MPI_Finalize; a network link closed
        return out;
    }
    ClusterRoot root(t, config, setup.out);
    out.run = rank_zero ? rank_zero(options, {&root}) : RunPipeline(options, {&root}).run();
    transport_slot().reset();
    return out;
}

// A wall without mpirun: rank 0 listens, each render rank connects and claims its rank.
ClusterRunResult run_network_wall(const RunOptions& options, const RankZeroRun& rank_zero) {
    if (!options.cluster_listen.empty() && !options.cluster_connect.empty())
        throw Error("--cluster-listen and --cluster-connect: a process is rank 0 (listen) or a render rank (connect), not both");
    if (launched_by_mpirun())
        throw Error("--cluster-listen / --cluster-connect start each rank by hand, without mpirun; under mpirun leave "
                    "them out (docs/cluster.md)");
    const RunSetup setup = resolve_run(options);
    const ClusterConfig config = read_cluster_config(options.cluster, setup.scene.display);
    const int k = static_cast<int>(config.ranks.size());
    const std::optional<devices::net::SessionKey> key = wall_key(config);
    if (!options.cluster_connect.empty()) {
        if (options.cluster_rank == 0)
            throw Error("--cluster-connect: give --rank R, the render rank this process draws (" + config.source +
                        " names 1.." + std::to_string(k) + ")");
        if (options.cluster_rank < 1 || options.cluster_rank > k)
            throw Error("--rank " + std::to_string(options.cluster_rank) + ": " + config.source + " names render ranks 1.." +
                        std::to_string(k));
        std::string host;
        std::uint16_t port = 0;
        devices::net::split_host_port(options.cluster_connect, "--cluster-connect", host, port);
        transport_slot() = make_member_transport(host, port, options.cluster_rank, k, key,
                                                 deadline_after(config.start_timeout_s));
        return run_this_rank(options, rank_zero, setup, config);
    }
    if (options.cluster_rank != 0) throw Error("--rank: only with --cluster-connect (rank 0 is the one that listens)");
    std::string host;
    std::uint16_t port = 0;
    devices::net::split_listen_address(options.cluster_listen, "--cluster-listen", host, port);
    transport_slot() = make_listener_transport(host, port, k, key);
    std::fprintf(stderr, "tridex: wall rank 0: %s; render ranks join with: tridex run ... --cluster %s "
                         "--cluster-connect THIS_HOST:%u --rank R\n",
                 transport_slot()->name().c_str(), options.cluster.c_str(),
                 static_cast<unsigned>(listener_port(*transport_slot())));
    return run_this_rank(options, rank_zero, setup, config);
}

}  // namespace

ClusterRunResult run_cluster_session(const RunOptions& options, const RankZeroRun& rank_zero) {
    if (!options.cluster_listen.empty() || !options.cluster_connect.empty()) return run_network_wall(options, rank_zero);
    if (options.cluster_rank != 0) throw Error("--rank: only with --cluster-connect");
    if (!cluster_supported()) (void)make_mpi_transport();  // throws the reason
    if (!launched_by_mpirun())
        throw Error("--cluster " + options.cluster + ": a cluster session is started by mpirun, one rank per machine "
                    "and rank 0 running the session: mpirun -np K+1 tridex run ... --cluster CONFIG, for a config "
                    "naming K render ranks (docs/wall.md)");
    const RunSetup setup = resolve_run(options);  // the wall's display config, and the options checked on every rank
    const ClusterConfig config = read_cluster_config(options.cluster, setup.scene.display);
    transport_slot() = make_mpi_transport();
    const int size = transport_slot()->size();
    if (size != static_cast<int>(config.ranks.size()) + 1)
        throw Error(config.source + ": names " + std::to_string(config.ranks.size()) + " render ranks, so the session needs mpirun -np " +
                    std::to_string(config.ranks.size() + 1) + "; it was started with " + std::to_string(size) + " ranks");
    return run_this_rank(options, rank_zero, setup, config);
}

void end_cluster_session(int code) {
    if (transport_slot()) transport_slot()->abort_all(code);
}

}  // namespace tridex::app
