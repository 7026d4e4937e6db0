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

#include "app/session/runtime/session_companion.hpp"
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
};

/// The joiner's companion of a run session. Made before the session (join() waits for the welcome, whose starting
/// model the session then loads), it follows the host until the host ends the session (ended()) or goes away
/// (failure(): the replica is kept, and --save still saves it).
class SharedJoin final : public SessionCompanion {
public:
    /// Seals `link` (a connection to the host, not polled yet) with `key` as the joiner. Throws tridex::Error as
    /// SealedLink does.
    SharedJoin(SharedJoinOptions options, std::unique_ptr<devices::net::DatagramLink> link,
               const devices::net::SessionKey& key);
    ~SharedJoin() override;
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
    void configure(SculptOptions& options) override;
    void starting(SessionRuntime& runtime) override;
    void before_present(const FrameShown& shown) override;
    void stopped(SessionRuntime& runtime, const FrameShown& last) override;
    /// starting()'s work: refuses a session whose spec (`here`) would build another model from the same stream than
    /// the host's (its clay grouping, islands or undo memory). Throws tridex::Error naming the setting.
    void start(const SessionSpec& here);
    /// stopped()'s work, once the sculpt thread stopped: stops the network thread and compares `model`'s digest with
    /// the host's final one (report.json shared.digest_match; a mismatch is a failure()).
    void finish(const compute::TriDexel& model);
    std::string failure() const override;
    std::string ended() const override;
    bool holds_session_open() const override { return true; }
    nlohmann::json report() const override;
    std::string report_key() const override { return "shared"; }
    /// The other sites heard from and not gone (others()).
    void add_presence(std::vector<SitePresence>& out) const override;
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
