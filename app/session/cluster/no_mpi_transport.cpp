// app/session/cluster/no_mpi_transport.cpp - a build without MPI (libopenmpi-dev not installed): cluster sessions are
// refused with the reason.
#include "app/session/cluster/cluster_transport.hpp"

#include "core/error.hpp"

namespace tridex::app {

bool cluster_supported() { return false; }

std::unique_ptr<ClusterTransport> make_mpi_transport() {
    throw Error("cluster: this build of tridex has no MPI (install Debian's openmpi-bin and libopenmpi-dev, then "
                "rebuild: make build)");
}

}  // namespace tridex::app
