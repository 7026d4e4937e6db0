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
};

/// Rank 0's companion. Sends the hello (the spec and the starting model's digest) when the threads are made; each
/// frame sends the frame message, waits for every render rank's ready (config timeout_s; start_timeout_s for the
/// first frame) and releases them with go just before rank 0 presents: the swap barrier. When the threads stop it
/// sends the last frame (every remaining record, and the final model's digest) and collects each rank's report.
/// A rank that does not answer in time, answers with an error, or holds another model than rank 0 at a check is a
/// failure(): the session ends, keeps its work and names the rank.
class ClusterRoot final : public SessionCompanion {
public:
    /// `transport` must be rank 0 with config.ranks.size() + 1 ranks; both must outlive this. Throws tridex::Error
    /// when the rank count does not match the config.
    ClusterRoot(ClusterTransport& transport, const ClusterConfig& config);
    void configure(SculptOptions& options) override;
    void starting(SessionRuntime& runtime) override;
    void before_present(const FrameShown& shown) override;
    void stopped(SessionRuntime& runtime, const FrameShown& last) override;
    std::string failure() const override { return stats_.failure; }
    nlohmann::json report() const override;
    std::string report_key() const override { return "cluster"; }
    const ClusterStats& stats() const { return stats_; }

private:
    FrameMessage message_of(const FrameShown& shown, compute::ToolStreamBuffer::Taken taken) const;
    void exchange(FrameMessage m, bool first);  // send, wait for readies, go
    void fail(const std::string& why);  // the first failure is kept (failure()); later ones are dropped
    // Render rank r's next answer by `deadline` (timeout_s: the wait, for the message); nullopt after fail() when none
    // came, it could not be read, or it says the rank failed. `waiting_for` names what was awaited ("frame 12").
    std::optional<RankAnswer> answer_from(int r, ClusterTransport::Clock::time_point deadline, double timeout_s,
                                          const std::string& waiting_for);

    ClusterTransport& transport_;
    const ClusterConfig& config_;
    compute::ToolStreamBuffer stream_;
    std::vector<double> last_present_s_;  // per render rank: its previous present, steady s
    double prev_newest_s_ = 0.0;          // the newest sample of the frame last released, steady s (0: none)
    ClusterStats stats_;
};

}  // namespace tridex::app
