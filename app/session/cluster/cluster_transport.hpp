// app/session/cluster/cluster_transport.hpp - how the ranks of a cluster session reach each other: messages between
// two ranks, each wait bounded, so that a rank that died or hangs is named instead of hanging the others.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace tridex::app {

/// Messages between the ranks of one cluster session (Open MPI's ranks: app/session/cluster/mpi_transport.cpp).
/// Only the thread that made it calls it.
class ClusterTransport {
public:
    using Clock = std::chrono::steady_clock;
    virtual ~ClusterTransport() = default;
    /// This process's rank, 0..size()-1.
    virtual int rank() const = 0;
    /// Ranks in the session.
    virtual int size() const = 0;
    /// Queues `bytes` for rank `to` and returns at once (the transport owns them until they are sent). Throws
    /// tridex::Error when the message cannot be queued (a rank out of range, the transport failed).
    virtual void send(int to, std::vector<unsigned char> bytes) = 0;
    /// The next message from rank `from`, waiting at most until `deadline`; nullopt when none came by then.
    /// Throws tridex::Error when the transport failed.
    virtual std::optional<std::vector<unsigned char>> receive(int from, Clock::time_point deadline) = 0;
    /// Waits until every queued send has left or `deadline` passed; false when some had not.
    virtual bool flush(Clock::time_point deadline) = 0;
    /// Ends every rank of the session at once with exit code `code` (after a failure, once this rank's work is
    /// kept). Does not return.
    [[noreturn]] virtual void abort_all(int code) = 0;
    /// The transport and its library, e.g. "Open MPI 4.1.4".
    virtual std::string name() const = 0;

    // ---- Membership: a transport whose render ranks are processes that come and go (a network wall). MPI's ranks
    // ---- are fixed at launch: the defaults below describe it (everyone present, nobody arrives or leaves).

    /// True when a render rank may connect after the session started, and a new process may take the place of one
    /// that failed (release()); false when the ranks are fixed at launch (MPI: a rank's failure ends the session).
    virtual bool open_membership() const { return false; }
    /// Rank 0 only: the render ranks (1..size()-1) whose process connected since the last call, in the order they
    /// came; a rank appears again when a new process took its place after release(). Never throws.
    virtual std::vector<int> arrivals() { return {}; }
    /// Rank 0 only: whether render rank `r` has a process connected now (one that arrived and was not released).
    virtual bool present(int r) const { (void)r; return true; }
    /// Rank 0 only: forgets render rank `r`'s process (it failed, or holds another model): it is disconnected once
    /// what was queued for it is sent, what came from it and was not received is dropped, later sends to it are
    /// dropped, and a new process may claim rank r (it then appears in arrivals()). Nothing for a closed membership.
    virtual void release(int r) { (void)r; }
};

/// The time `seconds` (s, finite, >= 0) from now: a deadline for ClusterTransport's waits.
inline ClusterTransport::Clock::time_point deadline_after(double seconds) {
    return ClusterTransport::Clock::now() +
           std::chrono::duration_cast<ClusterTransport::Clock::duration>(std::chrono::duration<double>(seconds));
}

/// True when this build can run cluster sessions (it was built with MPI).
bool cluster_supported();

/// True when this process was started by mpirun (Open MPI's environment).
bool launched_by_mpirun();

/// Initialises MPI (threads: funnelled; only the calling thread talks) and returns the transport over
/// MPI_COMM_WORLD; finalises MPI when destroyed (after a flush). Throws tridex::Error when this build has no MPI,
/// or MPI cannot start.
std::unique_ptr<ClusterTransport> make_mpi_transport();

}  // namespace tridex::app
