// app/session/shared/shared_host.hpp - the host of a shared session (`tridex run --host`): its sculpt thread is the one
// authority; a network thread takes the joiners' samples and requests into it (SiteIntake) and sends every site the
// ordered stream it applied, from the model the session started with. docs/shared.md.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/session/runtime/session_runtime.hpp"
#include "app/session/runtime/site_presence.hpp"
#include "app/session/shared/record_log.hpp"
#include "app/session/shared/shared_message.hpp"
#include "compute/journal/stream_buffer.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "compute/runtime/site_intake.hpp"
#include "devices/net/datagram_link.hpp"
#include "devices/net/sealed_link.hpp"

namespace tridex::app {

/// Where a host's joiners come from: each call hands the link of a newly connected peer, or nullptr when none is
/// waiting (an EnetHub's accept; a test's in-process shim ends). Called on the host's network thread only.
using PeerAccept = std::function<std::unique_ptr<devices::net::DatagramLink>()>;

/// How a host runs.
struct SharedHostOptions {
    devices::net::SessionKey key;   ///< the session's key: every joiner's link is sealed with it
    std::string name = "host";      ///< the host's person, as the joiners see it
    Vec3 colour{0.2, 0.6, 1.0};     ///< the host's tool colour, sRGB 0..1
    std::string out;                ///< the session's output folder: the starting model is written there
    double digest_check_s = 1.0;    ///< wall time between digest checks sent to the joiners, s (> 0)
    std::size_t max_records_per_message = 2048;  ///< a late joiner's backlog is sent in messages of at most this many
    /// Wall time the host keeps serving after its session ended, so that the last records and the end reach the
    /// joiners before it disconnects, s.
    double linger_s = 2.0;
};

/// What one joiner did (report.json `shared.joiners`).
struct JoinerReport {
    std::uint8_t site = 0;
    std::string name;
    std::string where;              ///< its address
    std::uint64_t samples = 0;      ///< tool samples it sent that were queued
    std::uint64_t requests = 0;     ///< undo, redo and stroke-close requests it sent
    std::uint64_t refusals = 0;     ///< of those, refused (SiteStrokes)
    std::uint64_t presence = 0;     ///< presence messages heard from it (about 30 a second; unreliable)
    std::uint64_t first_record = 0; ///< the first record it was sent: 0 from the start, else it joined late at it
    std::uint64_t bad_messages = 0; ///< messages it sent that could not be read (it was dropped at the first)
    std::uint64_t bytes_in = 0, bytes_out = 0;  ///< payload bytes received from it and sent to it
    double joined_s = 0.0, left_s = -1.0;       ///< wall time since the session started, s (-1: still there)
    std::uint64_t sealed_refused = 0;           ///< datagrams its sealed link refused (forged, replayed, ...)
};

/// A shared session's host: its network thread and the sculpt thread's wiring (the run session's side is
/// SharedHostSite, shared_site.hpp).
class SharedHost {
public:
    /// `accept` yields joiners' links (each is sealed here with options.key as the listener). Throws tridex::Error when
    /// options.digest_check_s is not > 0.
    SharedHost(SharedHostOptions options, PeerAccept accept);
    ~SharedHost();
    SharedHost(const SharedHost&) = delete;
    SharedHost& operator=(const SharedHost&) = delete;
    /// Before the session's threads are made: the sculpt thread streams to this host and takes the joiners' samples
    /// and requests from its intake.
    void configure(SculptOptions& options);
    /// How a model becomes the bytes of a .tdx file (the session's placement, spec and palette), on the network thread.
    using ModelBytes = std::function<std::vector<unsigned char>(const compute::TriDexel& model)>;
    /// Once the model is loaded, before the sculpt thread starts: keeps the starting model (`model`, and its .tdx
    /// file's bytes `start_tdx`), its digest and the session spec (`spec_json`) for the joiners, and starts the network
    /// thread. With `model_bytes`, a joiner that does not ask for the start (JoinMessage::from_start) joins with the
    /// model as it stands: a snapshot the sculpt thread takes (SculptThread::use_snapshots), its undo history, and
    /// the stream from there; without, every joiner gets the starting model and the whole stream. Throws
    /// tridex::Error when the host started already.
    void start(const compute::TriDexel& model, std::vector<unsigned char> start_tdx, std::string spec_json,
               ModelBytes model_bytes = {});
    /// Where this site's own tool (and tracked head) is, for the joiners to draw. Any thread.
    void set_own_presence(const SitePresence& p);
    /// The options it runs with.
    const SharedHostOptions& options() const { return o_; }
    /// stopped()'s work, once the sculpt thread stopped: sends the rest of the stream and the end with `model`'s digest,
    /// serves the joiners until they left or options.linger_s passed, and stops the network thread.
    void finish(const compute::TriDexel& model);
    /// What it did (report.json `shared`).
    nlohmann::json report() const;
    /// The other sites' tools as last heard (the joiners'), for drawing them. Any thread.
    std::vector<PresenceMessage> others() const;
    /// The joiners so far (a copy, at most 0.1 s old while the session runs, final after finish()). Any thread.
    std::vector<JoinerReport> joiners() const;

private:
    struct Joiner;
    void run_network();
    void serve_once();
    void accept_joiners();
    void poll_joiner(Joiner& j);
    void on_message(Joiner& j, const std::vector<std::uint8_t>& bytes);
    void on_join(Joiner& j, const JoinMessage& m);
    void leave(Joiner& j, const std::string& why);
    void send(Joiner& j, const std::vector<unsigned char>& bytes, bool reliable);
    void send_records();
    void send_backlog(Joiner& j);
    void send_refusals();
    void send_presence();
    void welcome_late_joiners();  // the snapshots taken: their welcomes and the stream since
    std::uint8_t site_for(const std::string& name);
    void copy_reports();  // the joiners' reports, for report() and joiners() (at most every 0.1 s, and at the end)
    double now_s() const;

    SharedHostOptions o_;
    PeerAccept accept_;
    compute::ToolStreamBuffer stream_;
    SiteIntake intake_;
    // The session as it started: sent to every joiner with the stream's records since.
    std::string spec_json_;
    std::vector<unsigned char> start_tdx_;
    std::uint64_t start_digest_ = 0;
    RecordLog log_;  // every record so far, packed in chunks (network thread)
    std::vector<std::unique_ptr<Joiner>> joiners_;  // network thread; reports copied under mutex_
    std::vector<std::string> site_names_;           // by site: who held it (a rejoin by name gets it again)
    mutable std::mutex mutex_;                      // guards the copies below
    std::vector<JoinerReport> reports_;
    std::vector<PresenceMessage> presence_;         // the joiners' newest
    PresenceMessage own_presence_;
    std::vector<SculptRefusal> refusals_;           // from the sculpt thread, to send
    struct Snapshot {
        SculptSnapshot snapshot;
        std::uint64_t records = 0;  // records streamed before it (its model holds them)
    };
    std::vector<Snapshot> snapshots_;               // from the sculpt thread, for late joiners
    ModelBytes model_bytes_;
    std::uint64_t own_refusals_ = 0;
    std::atomic<bool> stop_{false};
    std::atomic<bool> final_{false};                // the sculpt thread stopped: send the rest and the end
    std::uint64_t final_digest_ = 0;
    std::thread thread_;
    double started_s_ = 0.0;
    double last_check_s_ = 0.0, last_presence_s_ = 0.0, last_reports_s_ = 0.0;
    std::uint64_t checks_ = 0;
    std::uint64_t records_sent_ = 0;
    std::uint64_t log_bytes_ = 0;  // log_.bytes() after the last records sent
    std::uint64_t peers_refused_ = 0;  // peers whose handshake failed (another key, unsealed)
};

}  // namespace tridex::app
