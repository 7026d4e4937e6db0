// app/session/cluster/cluster_root.cpp - rank 0: the stream replicated frame by frame, the swap barrier, the checks.
#include "app/session/cluster/cluster_root.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "app/support/file_bytes.hpp"
#include "compute/journal/journal_format.hpp"
#include "compute/model/model_digest.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::app {

namespace {

using Clock = std::chrono::steady_clock;

double now_s() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }


}  // namespace

// ---- ClusterRoot ---------------------------------------------------------------------------------------------

ClusterRoot::ClusterRoot(ClusterTransport& transport, const ClusterConfig& config) : transport_(transport), config_(config) {
    const int want = static_cast<int>(config.ranks.size()) + 1;
    if (transport.size() != want)
        throw Error(config.source + ": names " + std::to_string(config.ranks.size()) + " render ranks, so the session needs " +
                    std::to_string(want) + " ranks (mpirun -np " + std::to_string(want) + "); it has " +
                    std::to_string(transport.size()));
    stats_.ranks = want;
    last_present_s_.assign(config.ranks.size(), 0.0);
    if (const char* v = std::getenv("OMPI_MCA_orte_abort_on_non_zero_status"); !v || std::string(v) != "0")
        std::fprintf(stderr, "tridex: cluster: mpirun ends every rank when one exits with an error, so a failing render rank "
                             "would take this session's unsaved work with it; launch with "
                             "--mca orte_abort_on_non_zero_status 0 (docs/cluster.md)\n");
}

void ClusterRoot::configure(SculptOptions& options) { options.streams.push_back(&stream_); }

void ClusterRoot::starting(SessionRuntime& runtime) {
    HelloMessage h;
    h.spec_json = spec_to_json(runtime.spec());
    h.initial_digest = compute::model_digest(runtime.workpiece().model);
    if (!runtime.spec().model_path.empty()) h.model_tdx = read_file_bytes(runtime.spec().model_path);
    const std::vector<unsigned char> bytes = encode_hello(h);
    for (int r = 1; r < transport_.size(); ++r) transport_.send(r, bytes);
    // The session starts when every viewport is ready to draw it: nothing sculpted goes unseen on the wall.
    const auto deadline = deadline_after(config_.start_timeout_s);
    for (int r = 1; r < transport_.size(); ++r) {
        const std::optional<RankAnswer> a = answer_from(r, deadline, config_.start_timeout_s, "the hello");
        if (a && a->frame != kHelloAnswerFrame)
            fail("render rank " + std::to_string(r) + " answered the hello with frame " + std::to_string(a->frame));
        if (!stats_.failure.empty()) throw Error(stats_.failure);
    }
}

FrameMessage ClusterRoot::message_of(const FrameShown& shown, compute::ToolStreamBuffer::Taken taken) const {
    FrameMessage m;
    m.frame = shown.frame;
    m.head = shown.head;
    if (shown.nav) {
        m.nav_pose = shown.nav->pose();
        m.nav_scale = shown.nav->scale();
    }
    m.eye_separation_m = shown.eye_separation_m;
    m.show_tool = shown.show_tool;
    m.tool_m = shown.tool_m;
    m.tool_orientation = shown.tool_orientation;
    m.tool = shown.tool;
    m.ao = std::clamp(shown.ao, 0.0, 1.0);
    if (shown.menu) m.menu = *shown.menu;
    m.others = shown.others;
    m.records = std::move(taken.records);
    m.check_digest = taken.digest;
    m.check_after = taken.digest_after;
    m.newest_sample_made_s = taken.newest_made_s;
    return m;
}

void ClusterRoot::fail(const std::string& why) {
    if (stats_.failure.empty()) stats_.failure = "cluster: " + why;
}

std::optional<RankAnswer> ClusterRoot::answer_from(int r, Clock::time_point deadline, double timeout_s,
                                                   const std::string& waiting_for) {
    const std::string who = "render rank " + std::to_string(r);
    try {
        const auto got = transport_.receive(r, deadline);
        if (!got) {
            fail(who + " did not answer " + waiting_for + " within " + format_number(timeout_s) +
                 " s (it died, hangs or its machine is unreachable)");
            return std::nullopt;
        }
        RankAnswer a = decode_answer(*got, who);
        if (!a.error.empty()) {
            fail(who + " failed at " + waiting_for + ": " + a.error);
            return std::nullopt;
        }
        return a;
    } catch (const Error& e) {
        fail(e.what());
        return std::nullopt;
    }
}

void ClusterRoot::exchange(FrameMessage m, bool first) {
    const std::size_t samples = [&] {
        std::size_t n = 0;
        for (const compute::JournalRecord& r : m.records) n += r.samples.size();
        return n;
    }();
    stats_.records += m.records.size();
    stats_.samples += samples;
    const bool checked = m.check_digest.has_value();
    const std::uint64_t frame = m.frame;
    const double newest = m.newest_sample_made_s;
    m.sent_s = now_s();
    const std::vector<unsigned char> bytes = encode_frame(m);
    stats_.frame_bytes.push_back(static_cast<double>(bytes.size()));
    ++stats_.frames;
    const auto t0 = Clock::now();
    try {
        for (int r = 1; r < transport_.size(); ++r) transport_.send(r, bytes);
    } catch (const Error& e) {
        fail(e.what());
        return;
    }
    const double timeout = first ? config_.start_timeout_s : config_.timeout_s;
    const auto deadline = deadline_after(timeout);
    double earliest = 0.0, latest = 0.0;
    for (int r = 1; r < transport_.size(); ++r) {
        const std::optional<RankAnswer> a = answer_from(r, deadline, timeout, "frame " + std::to_string(frame));
        if (!a) return;
        if (a->frame != frame) {
            fail("render rank " + std::to_string(r) + " answered frame " + std::to_string(a->frame) + " to frame " +
                 std::to_string(frame));
            return;
        }
        if (a->digest_mismatch) {
            fail("render rank " + std::to_string(r) + " holds another model than rank 0 at frame " + std::to_string(frame) +
                 " (digest " + compute::digest_hex(a->digest) + ", rank 0's " + compute::digest_hex(m.check_digest.value_or(0)) +
                 "): the replicas diverged; the wall would show a model that is not the one being sculpted");
            return;
        }
        if (a->previous_present_s > 0.0) {
            earliest = earliest == 0.0 ? a->previous_present_s : std::min(earliest, a->previous_present_s);
            latest = std::max(latest, a->previous_present_s);
            last_present_s_[static_cast<std::size_t>(r - 1)] = a->previous_present_s;
        }
    }
    stats_.ready_wait_ms.add(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    if (latest > 0.0) stats_.swap_spread_ms.add(1e3 * (latest - earliest));
    if (checked) ++stats_.checks;
    try {
        const std::vector<unsigned char> go = encode_go(frame);
        for (int r = 1; r < transport_.size(); ++r) transport_.send(r, go);
    } catch (const Error& e) {
        fail(e.what());
        return;
    }
    // The present of this frame is reported with the next answer: keep its newest sample until then.
    if (prev_newest_s_ > 0.0)
        for (double p : last_present_s_)
            if (p > prev_newest_s_) stats_.sample_to_present_ms.add(1e3 * (p - prev_newest_s_));
    prev_newest_s_ = newest;
}

void ClusterRoot::before_present(const FrameShown& shown) {
    if (!stats_.failure.empty()) return;
    if (shown.frame % static_cast<std::uint64_t>(config_.check_every_frames) == 0) stream_.request_digest();
    exchange(message_of(shown, stream_.take()), shown.frame == 0);
}

void ClusterRoot::stopped(SessionRuntime& runtime, const FrameShown& last) {
    if (!stats_.failure.empty()) return;
    // The threads have stopped: the model is final, and read here. Every record left goes out with its digest.
    compute::ToolStreamBuffer::Taken taken = stream_.take();
    taken.digest = compute::model_digest(runtime.workpiece().model);
    taken.digest_after = static_cast<std::uint32_t>(taken.records.size());
    FrameMessage m = message_of(last, std::move(taken));
    m.last = true;
    exchange(std::move(m), last.frame == 0);
    if (!stats_.failure.empty()) return;
    const auto deadline = deadline_after(config_.timeout_s);
    for (int r = 1; r < transport_.size(); ++r) {
        const std::optional<RankAnswer> a = answer_from(r, deadline, config_.timeout_s, "the end (its report)");
        if (!a) return;
        if (a->previous_present_s > 0.0 && prev_newest_s_ > 0.0 && a->previous_present_s > prev_newest_s_)
            stats_.sample_to_present_ms.add(1e3 * (a->previous_present_s - prev_newest_s_));
        stats_.rank_reports.push_back(a->report_json);
    }
    (void)transport_.flush(deadline);
}

nlohmann::json ClusterRoot::report() const {
    nlohmann::json ranks = nlohmann::json::array();
    for (const std::string& text : stats_.rank_reports) {
        try {
            ranks.push_back(nlohmann::json::parse(text));
        } catch (const nlohmann::json::exception&) {
            ranks.push_back(nullptr);
        }
    }
    double bytes_total = 0.0;
    for (double b : stats_.frame_bytes) bytes_total += b;
    return {{"transport", transport_.name()},
            {"config", config_.source},
            {"ranks", stats_.ranks},
            {"frames", stats_.frames},
            {"records", stats_.records},
            {"samples", stats_.samples},
            {"checks", stats_.checks},
            {"frame_bytes", summary_report_json(stats_.frame_bytes)},
            {"frame_bytes_mean", stats_.frames ? bytes_total / static_cast<double>(stats_.frames) : 0.0},
            {"ready_wait_ms", summary_report_json(stats_.ready_wait_ms)},
            {"sample_to_present_ms", summary_report_json(stats_.sample_to_present_ms)},
            {"swap_spread_ms", summary_report_json(stats_.swap_spread_ms)},
            {"failure", stats_.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(stats_.failure)},
            {"render_ranks", ranks}};
}

}  // namespace tridex::app
