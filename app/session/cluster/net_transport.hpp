// app/session/cluster/net_transport.hpp - a cluster session's ranks over the network (ENet over UDP, optionally
// sealed with the session's key), whose render ranks are processes that may come and go: a render rank joins a
// running wall, or a new process takes the place of one that failed. docs/cluster.md, "A wall without mpirun".
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "app/session/cluster/cluster_transport.hpp"
#include "devices/net/sealed_link.hpp"

namespace tridex::app {

/// Rank 0 of a network wall: listens on host:port (ENet over UDP; "" or "0.0.0.0" = every interface, port 0 = one the
/// system picks, which name() then gives as "... on HOST:PORT") for the processes of render ranks 1..render_ranks,
/// each of which claims its rank when it connects (make_member_transport). With a key, every datagram is sealed
/// (devices/net/sealed_link.hpp) and a process without the key never gets in. open_membership() is true: a rank's
/// process may connect at any time (arrivals()), and after release(r) a new process may claim rank r; a claim of a
/// rank that a connected process holds, out of range or of another protocol is answered with a refusal naming why,
/// and the process is disconnected. A message of any size is carried whole (split into datagrams and joined again).
/// A network thread of its own services the socket, so that peers are answered while the caller's thread is busy.
/// receive(r, ...) throws tridex::Error "render rank R left (...)" once rank r's process disconnected and nothing
/// from it is left to receive; send(r, ...) to an absent rank drops the message. abort_all tells every connected
/// process to end with the code, waits briefly for that to leave, and ends this process. Throws tridex::Error
/// "--cluster-listen HOST:PORT: ..." when it cannot listen there, or render_ranks is not 1..31.
std::unique_ptr<ClusterTransport> make_listener_transport(const std::string& host, std::uint16_t port, int render_ranks,
                                                          const std::optional<devices::net::SessionKey>& key);

/// A render rank of a network wall: connects to rank 0 at host:port, claims rank `rank` (1..render_ranks) and waits
/// until rank 0 accepts the claim or `deadline` passes. size() is render_ranks + 1. Throws tridex::Error
/// "--cluster-connect HOST:PORT: ..." naming why it could not join: no answer by the deadline, the handshake failed
/// (rank 0 holds another key, or none), or rank 0's refusal (its reason). Afterwards receive(0, ...) throws
/// tridex::Error "rank 0 left (...)" once rank 0's connection is gone, and an abort from rank 0 ends this process
/// with rank 0's code (after printing it on stderr).
std::unique_ptr<ClusterTransport> make_member_transport(const std::string& host, std::uint16_t port, int rank,
                                                        int render_ranks,
                                                        const std::optional<devices::net::SessionKey>& key,
                                                        ClusterTransport::Clock::time_point deadline);

}  // namespace tridex::app
