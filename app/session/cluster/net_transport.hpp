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
/// A network thread of its own services the socket, so that peers are answered while the caller's thread is busy;
/// the methods may be called from a thread other than the one that made it (one thread at a time). receive(r, ...) throws tridex::Error "render rank R
/// left (...)" once rank r's process disconnected and nothing from it is left to receive; send(r, ...) to an absent
/// rank drops the message, to a rank out of 1..render_ranks throws. flush() is true once every process present has
/// acknowledged every message sent to it whole; it is false at once while a process left before acknowledging all
/// (until release() of its rank or a new claim of it). abort_all tells every connected process to end with the
/// code, waits up to 1 s for that to arrive, and ends this process (std::_Exit). Throws tridex::Error
/// "--cluster-listen HOST:PORT: ..." when it cannot listen there, or render_ranks is not 1..31.
std::unique_ptr<ClusterTransport> make_listener_transport(const std::string& host, std::uint16_t port, int render_ranks,
                                                          const std::optional<devices::net::SessionKey>& key);

/// A render rank of a network wall: connects to rank 0 at host:port, claims rank `rank` (1..render_ranks) and waits
/// until rank 0 accepts the claim or `deadline` passes. size() is render_ranks + 1. Throws tridex::Error
/// "--cluster-connect HOST:PORT: ..." naming why it could not join: no answer by the deadline, the handshake failed
/// (rank 0 holds another key, or none), or rank 0's refusal (its reason). It talks to rank 0 only (send and receive
/// of another rank throw). Afterwards receive(0, ...) returns what had arrived, then throws tridex::Error "rank 0
/// left (...)" once rank 0's connection is gone (it is not made again); send(0, ...) then throws the same. An abort
/// from rank 0 does not end this process: receive(0, ...) and send(0, ...) throw tridex::Error "rank 0 ended the
/// session (code N)" at once, and the caller ends with code N. flush() is true once rank 0 acknowledged every
/// message whole. Its own abort_all(code) waits up to 1 s for flush() and ends this process (std::_Exit).
std::unique_ptr<ClusterTransport> make_member_transport(const std::string& host, std::uint16_t port, int rank,
                                                        int render_ranks,
                                                        const std::optional<devices::net::SessionKey>& key,
                                                        ClusterTransport::Clock::time_point deadline);

/// The UDP port a transport of make_listener_transport listens on (the one the system picked when port 0 was
/// asked); 0 for any other transport.
std::uint16_t listener_port(const ClusterTransport& transport);

}  // namespace tridex::app
