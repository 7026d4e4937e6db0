// app/session/cluster/cluster_root.hpp - rank 0 of a cluster session: the session as on one machine, plus the render
// ranks kept in step with it (the tool sample stream replicated, digest checks, the swap barrier, faults).
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "app/session/cluster/cluster_config.hpp"
#include "app/session/cluster/cluster_transport.hpp"
#include "app/session/cluster/frame_message.hpp"
#include "app/session/runtime/session_companion.hpp"
#include "app/session/report/session_report.hpp"
#include "compute/journal/stream_buffer.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/material_palette.hpp"
#include "core/math.hpp"
#include "core/duration_histogram.hpp"

namespace tridex::app {

/// What the cluster did, for report.json `cluster` and `tridex bench --cluster`.
struct ClusterStats {
    int ranks = 0;                               ///< ranks in the session (rank 0 included)
    std::uint64_t frames = 0;                    ///< frames sent
    std::vector<double> frame_bytes;             ///< bytes of each frame message
    /// Per frame: from sending it to the last rank's ready, ms.
    DurationHistogram ready_wait_ms = DurationHistogram::latency();
    /// Per frame with samples, per rank: newest sample made -> presented, ms.
    DurationHistogram sample_to_present_ms = DurationHistogram::latency();
    /// Per frame: latest minus earliest present over the render ranks, ms.
    DurationHistogram swap_spread_ms = DurationHistogram::fine();
    std::uint64_t checks = 0;                    ///< digest checks made on every rank
    std::uint64_t records = 0, samples = 0;      ///< records and samples replicated
    std::string failure;                         ///< why the session ended early ("" = it did not)
    std::vector<std::string> rank_reports;       ///< the render ranks' reports (JSON), in rank order
    /// A network wall (open membership): a render rank that failed and was let go, or a process that joined the
    /// running wall (a rank that came late, or took a failed one's place).
    struct Event {
        std::uint64_t frame = 0;      ///< the frame it happened at
        int rank = 0;                 ///< the render rank
        bool joined = false;          ///< true: it joined; false: it failed and was let go
        std::string why;              ///< let go: what failed
        std::uint64_t first_record = 0;  ///< joined: the stream's record its model stood at
        double join_s = 0.0;          ///< joined: from its connect to its first frame drawn in step, s
        double model_bytes = 0.0;     ///< joined: bytes of the model (.tdx) and history sent to it
    };
    std::vector<Event> events;
};

/// Rank 0's companion. Sends the hello (the spec and the starting model's digest) when the threads are made; each
/// frame sends the frame message, waits for every render rank's ready (config timeout_s; start_timeout_s for the
/// first frame) and releases them with go just before rank 0 presents: the swap barrier. When the threads stop it
/// sends the last frame (every remaining record, and the final model's digest) and collects each rank's report.
/// A rank that does not answer in time, answers with an error, or holds another model than rank 0 at a check is a
/// failure(): the session ends, keeps its work and names the rank. Over a transport with open membership (a network
/// wall) such a rank is let go instead (ClusterTransport::release; its viewports go dark, the session goes on), and a
/// render rank whose process connects while the wall runs joins it: the sculpt thread takes a snapshot of the model
/// when no stroke is open (SculptThread::ask_snapshot), saved as .tdx in `out` on a thread of its own; the rank gets
/// it with the undo history in its hello, loads it while the wall goes on, and takes part in the swap barrier from
/// the frame after its answer, with every record since the snapshot in that frame's message.
class ClusterRoot final : public SessionCompanion {
public:
    /// `transport` must be rank 0 with config.ranks.size() + 1 ranks; both must outlive this. `out`: the folder for
    /// a late joiner's model file. Throws tridex::Error when the rank count does not match the config.
    ClusterRoot(ClusterTransport& transport, const ClusterConfig& config, std::string out = ".");
    ~ClusterRoot() override;
    void configure(SculptOptions& options) override;
    void starting(SessionRuntime& runtime) override;
    void before_present(const FrameShown& shown) override;
    void stopped(SessionRuntime& runtime, const FrameShown& last) override;
    std::string failure() const override { return stats_.failure; }
    nlohmann::json report() const override;
    std::string report_key() const override { return "cluster"; }
    const ClusterStats& stats() const { return stats_; }

private:
    // Where a render rank stands: drawing in step, absent (never came, or let go), waiting for the snapshot it joins
    // with, or loading it (its hello sent).
    enum class Seat : std::uint8_t { kLive, kAbsent, kWaiting, kStarting };
    struct RankSeat {
        Seat seat = Seat::kLive;
        std::vector<compute::JournalRecord> pending;  // records since it asked, not sent to it yet
        std::uint64_t ask = 0;                        // kWaiting: its ask_snapshot count
        std::uint64_t first_record = 0;               // kStarting: its snapshot's first record
        double model_bytes = 0.0;                     // kStarting: its hello's bytes
        double arrived_s = 0.0, hello_s = 0.0;        // steady s: its connect, its hello sent
    };
    struct Saving;  // a snapshot on its way to .tdx bytes
    RankSeat& seat(int r) { return seats_[static_cast<std::size_t>(r - 1)]; }  // render rank r's

    FrameMessage message_of(const FrameShown& shown, compute::ToolStreamBuffer::Taken taken) const;
    void exchange(FrameMessage m, bool first);  // send, wait for readies, go
    void fail(const std::string& why);  // the first failure is kept (failure()); later ones are dropped
    // Render rank r is lost (`why`): the session fails, or over an open membership the rank is let go.
    void lost(int r, std::uint64_t frame, const std::string& why);
    // Render rank r's next answer by `deadline` (timeout_s: the wait, for the message); nullopt after lost() when none
    // came, it could not be read, or it says the rank failed. `waiting_for` names what was awaited ("frame 12").
    std::optional<RankAnswer> answer_from(int r, ClusterTransport::Clock::time_point deadline, double timeout_s,
                                          const std::string& waiting_for, std::uint64_t frame);
    void start_open(const HelloMessage& hello);  // an open membership's start: the ranks that come in time
    void admit(std::uint64_t frame);             // arrivals asked a snapshot; snapshots saved and sent; answers taken
    void send_late_hellos(std::vector<unsigned char> tdx, std::uint64_t frame);

    ClusterTransport& transport_;
    const ClusterConfig& config_;
    std::string out_;
    compute::ToolStreamBuffer stream_;
    std::vector<RankSeat> seats_;           // per render rank (index r - 1)
    SculptThread* sculpt_ = nullptr;        // asked for snapshots (open membership)
    std::string spec_json_;                 // the session, for the late joiners' hellos and model files
    Mat4 to_world_{1.0};
    MaterialPalette palette_ = default_material_palette();
    std::mutex snapshot_mutex_;             // guards snapshot_ (filled on the sculpt thread)
    std::optional<SculptSnapshot> snapshot_;
    std::uint64_t snapshot_first_ = 0;      // the stream's record after the snapshot
    std::unique_ptr<Saving> saving_;
    std::vector<double> last_present_s_;  // per render rank: its previous present, steady s
    double prev_newest_s_ = 0.0;          // the newest sample of the frame last released, steady s (0: none)
    ClusterStats stats_;
};

}  // namespace tridex::app
