// app/session/shared/shared_join.hpp - a joiner of a shared session (`tridex run --join HOST:PORT`): it builds its
// replica from the host's starting model, follows the host's ordered stream on its own sculpt thread (contouring,
// drawing and its own haptic loop on its own replica), and sends its tool's samples and requests to the host.
// docs/shared.md.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/session/runtime/session_runtime.hpp"
#include "app/session/runtime/site_presence.hpp"
#include "app/session/shared/shared_message.hpp"
#include "compute/runtime/site_intake.hpp"
#include "devices/net/datagram_link.hpp"
#include "devices/net/sealed_link.hpp"

namespace tridex::app {

/// How a joiner joins.
struct SharedJoinOptions {
    std::string name = "guest";      ///< the person, as the others see them (1..64 bytes)
    Vec3 colour{0.95, 0.45, 0.1};    ///< their tool's colour, sRGB 0..1
    std::string out;                 ///< the session's output folder: the host's starting model is written there
    double join_timeout_s = 15.0;    ///< how long to wait for the host's welcome, s
    /// Ask for the session's starting model and the whole stream (a cluster wall, whose render ranks replay from the
    /// start), not the model as it stands.
    bool from_start = false;
};

/// A shared session's joiner: its link to the host, its network thread and the sculpt thread's wiring (the run
/// session's side is SharedJoinSite, shared_site.hpp). Made before the session (join() waits for the welcome, whose
/// starting model the session then loads), it follows the host until the host ends the session (ended()) or goes
/// away (failure(): the replica is kept, and --save still saves it).
class SharedJoin {
public:
    /// Seals `link` (a connection to the host, not polled yet) with `key` as the joiner. Throws tridex::Error as
    /// SealedLink does.
    SharedJoin(SharedJoinOptions options, std::unique_ptr<devices::net::DatagramLink> link,
               const devices::net::SessionKey& key);
    ~SharedJoin();
    SharedJoin(const SharedJoin&) = delete;
    SharedJoin& operator=(const SharedJoin&) = delete;
    /// What join() gives: the host's welcome (its model bytes handed over to the file) and the starting model's file.
    struct Joined {
        WelcomeMessage welcome;
        std::string start_path;  ///< `<out>/shared_start.tdx`
    };
    /// Connects, sends the join and waits for the welcome (records that follow it are kept for the sculpt thread, and
    /// from then on a thread of its own serves the link); writes the host's starting model to
    /// `<out>/shared_start.tdx`. Throws tridex::Error naming the host when it cannot be reached, the handshake fails
    /// (another key), the host turns the join away (its reason), or no welcome comes within the timeout.
    Joined join();
    /// Before the session's threads are made: the sculpt thread follows the host's stream (SculptThread::follow_host)
    /// and hands this site's own samples and requests here, for the host. Throws tridex::Error before join().
    void configure(SculptOptions& options);
    /// Where this site's own tool (and tracked head) is, for the others to draw. Any thread.
    void set_own_presence(const SitePresence& p);
    /// The host's welcome (its model bytes handed over to the file). Valid after join().
    const WelcomeMessage& welcome() const { return welcome_; }
    /// The host's address ("HOST:PORT"), for messages.
    const std::string& host() const { return host_; }
    /// The options it runs with.
    const SharedJoinOptions& options() const { return o_; }
    /// Once the sculpt thread stopped, once the sculpt thread stopped: stops the network thread and compares `model`'s digest with
    /// the host's final one (report.json shared.digest_match; a mismatch is a failure()).
    void finish(const compute::TriDexel& model);
    /// Why it cannot go on (the host went away, a digest or mark mismatch); "" while it can. Any thread.
    std::string failure() const;
    /// Why the session ends now, normally (the host ended it); "" while it goes on. Any thread.
    std::string ended() const;
    /// What it did (report.json `shared`).
    nlohmann::json report() const;
    /// The other sites' tools as last heard (the host's and other joiners'), for drawing them. Any thread.
    std::vector<PresenceMessage> others() const;

private:
    void run_network();
    bool poll_once();  // one pass over the link; false when it ended
    void on_message(const std::vector<std::uint8_t>& bytes);
    void push_records(const RecordsMessage& m);
    void fail(const std::string& why);

    SharedJoinOptions o_;
    std::unique_ptr<devices::net::SealedLink> link_;
    std::string host_;  // the host's address, for messages
    SiteIntake intake_;
    WelcomeMessage welcome_;
    bool welcomed_ = false;
    std::thread thread_;
    std::atomic<bool> stop_{false};
    mutable std::mutex mutex_;  // guards what follows
    std::vector<ToolSample> outbox_;          // own samples from the sculpt thread, to send
    std::vector<SculptRequest> requests_out_;  // own requests, to send
    PresenceMessage own_presence_;
    std::vector<PresenceMessage> others_;
    std::string failure_, ended_;
    EndMessage end_;
    bool end_heard_ = false;
    std::uint64_t records_in_ = 0, samples_out_ = 0, requests_sent_ = 0, refusals_ = 0, checks_ = 0;
    std::uint64_t bytes_in_ = 0, bytes_out_ = 0;
    std::uint64_t final_digest_ = 0;
    bool digest_match_ = false;
    double last_presence_s_ = 0.0;
};

}  // namespace tridex::app
