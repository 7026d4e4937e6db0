// app/input/dtrack_head.cpp - DTrack head provider and its report.
#include "app/input/dtrack_head.hpp"

#include <charconv>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace tridex::app {
namespace {

std::int64_t steady_ns(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
}

bool whole_number(std::string_view s, int& out) {
    if (s.empty()) return false;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && p == s.data() + s.size();
}

}  // namespace

void parse_port_and_id(std::string_view text, const std::string& option, const std::string& id_name, int id_count,
                       const std::string& usage, int& port, int& id) {
    const std::size_t colon = text.find(':');
    int p = 0;
    if (!whole_number(text.substr(0, colon), p) || p < 1 || p > 65535)
        throw Error(option + ": the DTrack UDP port must be a whole number in 1..65535" + usage);
    port = p;
    if (colon != std::string_view::npos) {
        int i = 0;
        if (!whole_number(text.substr(colon + 1), i) || i < 0 || i >= id_count)
            throw Error(option + ": the " + id_name + " must be a whole number in 0.." + std::to_string(id_count - 1) +
                        usage);
        id = i;
    }
}

void parse_dtrack_head_option(const std::string& value, int& port, int& body) {
    const std::string_view v(value);
    const std::string usage = " (expected dtrack:PORT[:BODY], e.g. dtrack:5000:0)";
    if (v.rfind("dtrack:", 0) != 0) throw Error("--head: '" + value + "' is not dtrack:PORT[:BODY]" + usage);
    parse_port_and_id(v.substr(7), "--head", "DTrack body id", devices::kDTrackKeptBodies, usage, port, body);
}

DTrackHead::DTrackHead(const DTrackHeadSettings& s, std::shared_ptr<devices::DTrackReceiver> shared)
    : settings_(s), receiver_(std::move(shared)), tracker_(s.fallback, s.timeout_s), origin_ns_(steady_ns(std::chrono::steady_clock::now())) {
    if (s.body < 0 || s.body >= devices::kDTrackKeptBodies)
        throw Error("DTrack head body " + std::to_string(s.body) + ": must be in 0.." +
                    std::to_string(devices::kDTrackKeptBodies - 1));
    if (!receiver_) receiver_ = std::make_shared<devices::DTrackReceiver>(s.port, s.bind_address);
}

void DTrackHead::set_session_origin(std::chrono::steady_clock::time_point origin) { origin_ns_ = steady_ns(origin); }

Pose DTrackHead::head_at(double t_s) {
    const devices::DTrackBodySample& s = receiver_->latest().bodies[static_cast<std::size_t>(settings_.body)];
    if (s.seen && s.datagram != last_datagram_) {
        last_datagram_ = s.datagram;
        untracked_ = !s.body.tracked();
        if (!untracked_) {
            last_position_m_ = s.body.position_m;
            const Pose head = settings_.tracker_to_wall * s.body.pose() * settings_.head_to_eyes;
            tracker_.push(head, static_cast<double>(s.receipt_ns - origin_ns_) * 1e-9);
            pending_latency_ = true;
            pending_receipt_ns_ = s.receipt_ns;
        }
    }
    const Pose p = tracker_.head_at(t_s);
    if (tracker_.status().tracked) {
        ++frames_tracked_;
        if (pending_latency_) {
            pending_latency_ = false;
            latency_ms_.add(static_cast<double>(steady_ns(std::chrono::steady_clock::now()) - pending_receipt_ns_) *
                            1e-6);
        }
    } else {
        ++frames_stale_;
        pending_latency_ = false;
    }
    return p;
}

std::string DTrackHead::note() const {
    const std::string who = "DTrack body " + std::to_string(settings_.body) + " on UDP port " + std::to_string(port());
    const renderer::TrackerStatus& st = tracker_.status();
    if (st.tracked) return who + ": tracked" + (untracked_ ? " (holding the last pose: DTrack says quality -1)" : "");
    if (untracked_) return who + ": not tracked (quality -1); " + st.note;
    if (last_datagram_ == 0) {
        const devices::DTrackReceiverStats rs = receiver_->stats();
        return who + ": no sample of this body yet (" + std::to_string(rs.accepted) + " datagrams accepted, " +
               std::to_string(rs.rejected) + " rejected); using the fallback head pose";
    }
    return who + ": " + st.note;
}

nlohmann::json DTrackHead::report_json() const {
    using nlohmann::json;
    const devices::DTrackReceiverStats rs = receiver_->stats();
    json reasons = json::object();
    for (std::size_t k = 1; k < rs.by_reason.size(); ++k)
        if (rs.by_reason[k] > 0) reasons[devices::to_string(static_cast<devices::DTrackReject>(k))] = rs.by_reason[k];
    json last = nullptr;
    if (last_position_m_) last = json::array({last_position_m_->x, last_position_m_->y, last_position_m_->z});
    return json{{"provider", "dtrack"},
                {"port", port()},
                {"body", settings_.body},
                {"frames_tracked", frames_tracked_},
                {"frames_stale", frames_stale_},
                {"fallbacks", tracker_.status().fallbacks},
                {"last_position_m", last},
                {"latency_ms",
                 {{"median", latency_ms_.percentile_ms(0.5)},
                  {"p99", latency_ms_.percentile_ms(0.99)},
                  {"max", latency_ms_.max_ms()},
                  {"count", latency_ms_.count()},
                  {"from", "datagram receipt (receiver thread) to the frame's head_at() that first used it"}}},
                {"datagrams", rs.datagrams},
                {"accepted", rs.accepted},
                {"rejected", rs.rejected},
                {"rejected_by_reason", reasons},
                {"bodies_dropped", rs.bodies_dropped},
                {"note", note()}};
}

}  // namespace tridex::app
