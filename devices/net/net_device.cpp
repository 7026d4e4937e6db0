// devices/net/net_device.cpp - handshake, state intake, force and snapshot output of the net driver.
#include "devices/net/net_device.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "core/error.hpp"
#include "devices/net/surface_codec.hpp"

namespace tridex::devices::net {

namespace {

double steady_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void require_positive(double v, const char* field) {
    if (!(std::isfinite(v) && v > 0.0))
        throw Error(std::string("NetDeviceOptions.") + field + " = " + std::to_string(v) + " must be finite and > 0");
}

}  // namespace

NetDevice::NetDevice(std::unique_ptr<DatagramLink> link, NetDeviceOptions options)
    : link_(std::move(link)), opt_(std::move(options)) {
    require_positive(opt_.period_s, "period_s");
    require_positive(opt_.watchdog_s, "watchdog_s");
    require_positive(opt_.give_up_s, "give_up_s");
    if (!(std::isfinite(opt_.snapshot_interval_s) && opt_.snapshot_interval_s >= 0.0))
        throw Error("NetDeviceOptions.snapshot_interval_s = " + std::to_string(opt_.snapshot_interval_s) +
                    " must be finite and >= 0");
    if (!opt_.clock) opt_.clock = steady_s;
    profile_.name = "net (not connected)";
    out_.reserve(64 * 1024);
    ev_.data.reserve(64 * 1024);
    start_link_thread();
}

NetDevice::~NetDevice() { stop_link_thread(); }

void NetDevice::start_link_thread() {
    if (!opt_.link_thread || link_thread_.joinable()) return;
    {
        std::lock_guard lock(snap_mutex_);
        stop_thread_ = false;
    }
    link_thread_ = std::thread(&NetDevice::link_thread_main, this);
}

void NetDevice::stop_link_thread() noexcept {
    if (!link_thread_.joinable()) return;
    {
        std::lock_guard lock(snap_mutex_);
        stop_thread_ = true;
    }
    snap_cv_.notify_one();
    link_thread_.join();
}

void NetDevice::link_thread_main() {
    std::unique_lock lock(snap_mutex_);
    while (!stop_thread_) {
        snap_cv_.wait_for(lock, std::chrono::milliseconds(2));
        if (stop_thread_) break;
        lock.unlock();
        service();
        lock.lock();
    }
}

void NetDevice::observe_tool_scale(double scale) {
    if (opt_.mode == RenderingMode::kLocal && std::isfinite(scale) && scale > 0.0)
        tool_scale_.store(scale, std::memory_order_relaxed);
}

void NetDevice::service() {
    std::lock_guard link(link_mutex_);
    if (!loop_on_) pump();  // keep-alive: acknowledgements, pings, a welcome, a refusal
    if (opt_.mode != RenderingMode::kLocal || !welcomed_) return;
    // A resized tool: the server's loop gets the scaled contact points (a new revision).
    if (const double s = tool_scale_.load(std::memory_order_relaxed); have_contact_ && s != sent_scale_) {
        const std::uint32_t revision = contact_.revision + 1;
        contact_ = contact_base_;
        contact_.revision = revision;
        contact_.tool_radius_m *= s;
        contact_.point_radius_m *= s;
        for (int i = 0; i < contact_.point_count; ++i) contact_.point_local_m[static_cast<std::size_t>(i)] *= s;
        sent_scale_ = s;
        if (loop_on_) {
            encode(header(++reliable_seq_), contact_, out_);
            link_->send(out_, true);
        } else {
            contact_pending_ = true;
        }
    }
    const double now = opt_.clock();
    bool send = false;
    {
        std::lock_guard snap(snap_mutex_);
        const bool fresh = offered_seq_ != 0 && offered_seq_ != sent_surface_seq_;
        if (fresh && (sent_surface_seq_ == 0 || resend_surface_ || now - sent_surface_s_ >= opt_.snapshot_interval_s)) {
            sent_.swap(offered_);
            sent_surface_seq_ = offered_seq_;
            send = true;
        }
    }
    send = send || (resend_surface_ && sent_surface_seq_ != 0);
    if (!send) return;
    // The header is written now: its sequence number, time stamp and echo are the link's at the moment of sending.
    Header h = header(++reliable_seq_);
    h.type = MsgType::kSurface;
    std::vector<std::uint8_t> head;
    encode_header(h, head);
    std::copy(head.begin(), head.end(), sent_.begin());
    link_->send(sent_, true);
    sent_surface_s_ = now;
    resend_surface_ = false;
    ++snapshots_sent_;
}

void NetDevice::on_open() { start_link_thread(); }

void NetDevice::on_close() noexcept { stop_link_thread(); }

void NetDevice::on_disable() noexcept {
    std::lock_guard link(link_mutex_);
    loop_on_ = false;
}

std::uint64_t NetDevice::now_us() const { return static_cast<std::uint64_t>(std::llround(opt_.clock() * 1e6)) + 1; }

Header NetDevice::header(std::uint32_t seq) {
    Header h;
    h.version = opt_.version;
    h.seq = seq;
    h.sent_us = now_us();
    h.echo_us = peer_sent_us_;
    return h;
}

void NetDevice::note(const std::string& event) {
    if (events_.size() > 2000) return;  // the first events say what happened; a flapping link need not fill memory
    if (!events_.empty()) events_ += "; ";
    events_ += event;
}

void NetDevice::send_hello() {
    Hello hello;
    hello.mode = opt_.mode;
    hello.period_us = static_cast<std::uint32_t>(std::llround(opt_.period_s * 1e6));
    encode(header(++hello_seq_), hello, out_);
    link_->send(out_, true);
}

void NetDevice::set_contact(const ContactMsg& contact) {
    std::lock_guard link(link_mutex_);
    const std::uint32_t revision = have_contact_ ? contact_.revision + 1 : contact.revision;
    contact_ = contact;
    contact_.revision = revision;
    contact_base_ = contact;
    sent_scale_ = 1.0;
    tool_scale_.store(1.0, std::memory_order_relaxed);
    have_contact_ = true;
    contact_pending_ = true;  // sent when the loop starts (on_enable), so no reliable datagram waits unacknowledged
                              // while the session finishes its set-up without polling the link
}

bool NetDevice::handshake() {
    std::lock_guard link(link_mutex_);
    pump();
    if (!refusal_.empty()) throw Error(refusal_);
    if (!ever_welcomed_) {  // a handshake that cannot succeed fails at once: keys differ, or one side is sealed
        std::string failure = link_->handshake_failure();
        if (failure.empty() && reached_ && drops_.total() > 0)
            failure = "the handshake failed: it sends datagrams this session cannot read (is it sealed? give this "
                      "session the same key: --key-file or --passphrase-env, or the scene's device.key_file or "
                      "device.passphrase_env)";
        if (!failure.empty()) throw Error("net: the device server at " + std::string(link_->where()) + ": " + failure);
    }
    if (welcomed_ && !have_state_) {  // the first state may have been lost: keep the server's watchdog fed until one comes
        encode_heartbeat(header(++tx_seq_), out_);
        link_->send(out_, false);
    }
    return welcomed_ && have_state_;
}

void NetDevice::wait_for_server(double timeout_s) {
    const double end = steady_s() + timeout_s;
    while (!handshake()) {
        if (steady_s() > end) {
            const std::string within = " within " + std::to_string(static_cast<int>(std::ceil(timeout_s))) + " s";
            if (link_->reached() || reached_)
                throw Error(std::string("net: the device server at ") + link_->where() +
                            " accepted the connection but did not complete the handshake" + within +
                            " (is one side sealed and the other not? both need the same --key-file or "
                            "--passphrase-env)");
            throw Error(std::string("net: no device server answered at ") + link_->where() + within +
                        " (is `tridex device-server --listen " + link_->where() + "` running there?)");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    // Let the transport take the acknowledgements of what the handshake sent reliably (the contact parameters), so a
    // session that then spends seconds loading does not find them unacknowledged and its connection timed out.
    const double settle = steady_s() + 0.1;
    while (steady_s() < settle) {
        {
            std::lock_guard link(link_mutex_);
            pump();
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

void NetDevice::pump() {
    while (link_->poll(ev_)) {
        switch (ev_.kind) {
            case LinkEvent::kConnected:
                reached_ = true;
                welcomed_ = false;
                send_hello();
                break;
            case LinkEvent::kDisconnected:
                if (welcomed_) note("the device server at " + std::string(link_->where()) + " disconnected");
                welcomed_ = false;
                break;
            case LinkEvent::kData: handle(ev_.data); break;
        }
    }
}

void NetDevice::handle(const std::vector<std::uint8_t>& d) {
    Header h;
    DropReason r = decode_header(d.data(), d.size(), h, opt_.version);
    if (r == DropReason::kVersion && h.type == MsgType::kRefuse) r = DropReason::kNone;  // every version reads it
    if (r != DropReason::kNone) {
        drops_.add(r);
        return;
    }
    switch (h.type) {
        case MsgType::kRefuse: {
            std::string reason;
            if ((r = decode_refuse(d.data(), d.size(), reason)) != DropReason::kNone) break;
            refusal_ = reason.empty() ? "net: the device server refused this session" : reason;
            note(refusal_);
            raise_fault(kFaultIo);
            return;
        }
        case MsgType::kWelcome: {
            Welcome w;
            if ((r = decode(d.data(), d.size(), w)) != DropReason::kNone) break;
            if (!ever_welcomed_) {
                profile_ = profile_from(w);
            } else if (w.name != profile_.name || w.max_force_n != profile_.max_force_n) {
                refusal_ = "net: the device server at " + std::string(link_->where()) + " now serves '" + w.name +
                           "' instead of '" + profile_.name + "'; start the session again";
                note(refusal_);
                raise_fault(kFaultIo);
                return;
            } else {
                note("the device server at " + std::string(link_->where()) + " welcomed this session again");
            }
            welcomed_ = ever_welcomed_ = true;
            state_seq_valid_ = false;
            rebase_time_ = have_state_;
            if (opt_.mode == RenderingMode::kLocal) {
                if (have_contact_) {
                    encode(header(++reliable_seq_), contact_, out_);
                    link_->send(out_, true);
                }
                resend_surface_ = true;  // a restarted server has no snapshot: send the newest again
            }
            return;
        }
        case MsgType::kState: {
            StateMsg m;
            if ((r = decode(d.data(), d.size(), m)) != DropReason::kNone) break;
            if (!welcomed_) {
                r = DropReason::kUnexpected;
                break;
            }
            if (state_seq_valid_ && static_cast<std::int32_t>(h.seq - state_seq_) <= 0) return;  // late duplicate
            if (state_seq_valid_) lost_ += h.seq - state_seq_ - 1;
            state_seq_ = h.seq;
            state_seq_valid_ = true;
            peer_sent_us_ = h.sent_us;
            const double now = opt_.clock();
            if (h.echo_us > 0) {
                const std::uint64_t t = now_us();
                if (t >= h.echo_us) rtt_us_[rtt_count_++ % kRttSamples] = static_cast<float>(t - h.echo_us);
            }
            if (rebase_time_) {  // a restarted server's clock starts again: keep the session's time increasing
                t_offset_s_ = state_.t_s + opt_.period_s - m.state.t_s;
                rebase_time_ = false;
                // The old server's counters are kept, the new one's start from zero.
                server_lost_base_ += server_.lost;
                server_trips_base_ += server_.watchdog_trips;
                server_stale_base_ += server_.stale_snapshots;
            }
            server_ = m;
            state_ = m.state;
            have_tool_ = opt_.mode == RenderingMode::kLocal && m.has_tool;
            tool_ = m.tool;
            state_.t_s += t_offset_s_;
            have_state_ = fresh_state_ = true;
            ++states_;
            if (first_state_rx_s_ < 0.0) {
                first_state_rx_s_ = now;
                states_at_enable_ = 1;
            }
            last_state_rx_s_ = now;
            return;
        }
        default: r = DropReason::kUnexpected; break;
    }
    drops_.add(r);
}

void NetDevice::on_enable() {
    std::lock_guard link(link_mutex_);
    loop_on_ = true;
    pump();
    if (contact_pending_ && welcomed_ && opt_.mode == RenderingMode::kLocal) {
        encode(header(++reliable_seq_), contact_, out_);
        link_->send(out_, true);
    }
    contact_pending_ = false;
    last_state_rx_s_ = std::max(last_state_rx_s_, opt_.clock());
    first_state_rx_s_ = last_state_rx_s_;  // the rate counts from the loop's start, not from the handshake
    states_at_enable_ = states_;
}

bool NetDevice::do_read(DeviceState& out) {
    std::unique_lock link(link_mutex_, std::try_to_lock);
    if (!have_state_) return false;  // never connected: there is no sample to give
    if (!link.owns_lock()) {  // the link thread is handing a snapshot to the transport: the previous state, no I/O
        ++missed_;
        read_fresh_ = false;
        if (have_tool_) ++stale_tool_;
        out = state_;
        return true;
    }
    pump();
    const double silent = opt_.clock() - last_state_rx_s_;
    if (silent > opt_.watchdog_s && !down_) {
        down_ = true;
        ++outages_;
        raise_fault(kFaultIo);
        note("no device state from " + std::string(link_->where()) + " for " +
             std::to_string(static_cast<int>(std::lround(opt_.watchdog_s * 1e3))) + " ms: force zeroed");
    } else if (down_ && fresh_state_) {
        down_ = false;
        note("device states from " + std::string(link_->where()) + " again");
    }
    if (down_) ++zeroed_;
    if (!fresh_state_) ++missed_;
    read_fresh_ = fresh_state_ && !down_;
    if (have_tool_ && !read_fresh_) ++stale_tool_;
    fresh_state_ = false;
    if (down_ && silent > opt_.give_up_s) {
        note("gave up after " + std::to_string(static_cast<int>(opt_.give_up_s)) + " s without the device server");
        return false;
    }
    out = state_;
    return true;
}

void NetDevice::do_write(const Vec3& force_n, const Vec3& torque_nm) {
    std::unique_lock link(link_mutex_, std::try_to_lock);
    if (!link.owns_lock() || !welcomed_) return;  // a datagram skipped: the next tick's goes
    if (opt_.mode == RenderingMode::kDistributed) {
        ForceMsg m;
        // While the link is down the server holds zero force; a stale force must not reach it on the way back.
        m.force_n = down_ ? Vec3(0.0) : force_n;
        m.torque_nm = down_ ? Vec3(0.0) : torque_nm;
        encode(header(++tx_seq_), m, out_);
    } else {
        encode_heartbeat(header(++tx_seq_), out_);
    }
    link_->send(out_, false);
}

void NetDevice::observe_surface(const ActiveSurface& surface) {
    if (opt_.mode != RenderingMode::kLocal || surface.sequence == 0) return;
    {
        std::lock_guard snap(snap_mutex_);
        if (surface.sequence == offered_seq_) return;
        encode_surface(Header{}, surface, offered_);  // the header is rewritten when sent
        offered_seq_ = surface.sequence;
    }
    snap_cv_.notify_one();
}

bool NetDevice::remote_tool(RemoteToolSample& out) const {
    if (!have_tool_) return false;
    out = tool_;
    out.stale = !read_fresh_;
    return true;
}

DeviceLinkStats NetDevice::link_stats() const {
    std::lock_guard link(link_mutex_);
    DeviceLinkStats s;
    s.exchanges = states_;
    s.missed_frames = missed_;
    s.malformed_frames = drops_.total() + server_.malformed;
    s.zeroed_ticks = zeroed_;
    s.link_mode = to_string(opt_.mode);
    if (link_) {
        s.sealed = link_->sealed();
        s.seal_refused = link_->refused();
    }
    const std::size_t n = std::min(rtt_count_, kRttSamples);
    if (n > 0) {
        std::vector<float> v(rtt_us_.begin(), rtt_us_.begin() + static_cast<std::ptrdiff_t>(n));
        std::sort(v.begin(), v.end());
        s.rtt_median_us = v[n / 2];
        s.rtt_p99_us = v[std::min(n - 1, static_cast<std::size_t>(0.99 * static_cast<double>(n)))];
    }
    s.lost = lost_ + server_lost_base_ + server_.lost;
    if (states_ > states_at_enable_ && last_state_rx_s_ > first_state_rx_s_)
        s.rate_hz = static_cast<double>(states_ - states_at_enable_) / (last_state_rx_s_ - first_state_rx_s_);
    s.stale_snapshots = server_stale_base_ + server_.stale_snapshots;
    s.stale_tool_samples = stale_tool_;
    s.link_outages = outages_;
    s.server_watchdog_trips = server_trips_base_ + server_.watchdog_trips;
    s.link_events = events_;
    if (down_) s.down_for_s = std::max(0.0, opt_.clock() - last_state_rx_s_);
    return s;
}

}  // namespace tridex::devices::net
