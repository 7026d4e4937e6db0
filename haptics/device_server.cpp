// haptics/device_server.cpp - the serving tick: datagrams in, one device exchange, the state out.
#include "haptics/device_server.hpp"

#include <sys/prctl.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <ctime>

#include "core/error.hpp"
#include "core/thread_name.hpp"
#include "devices/net/surface_codec.hpp"
#include "haptics/realtime.hpp"

namespace tridex::haptics {

namespace net = devices::net;

namespace {

double steady_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

DeviceServer::DeviceServer(devices::HapticDevice& device, net::DatagramLink& link, DeviceServerConfig cfg)
    : device_(device), link_(link), cfg_(std::move(cfg)) {
    if (!(std::isfinite(cfg_.period_s) && cfg_.period_s > 0.0))
        throw Error("DeviceServerConfig.period_s = " + std::to_string(cfg_.period_s) + " must be finite and > 0");
    if (!(std::isfinite(cfg_.watchdog_s) && cfg_.watchdog_s > 0.0))
        throw Error("DeviceServerConfig.watchdog_s = " + std::to_string(cfg_.watchdog_s) + " must be finite and > 0");
    if (!cfg_.clock) cfg_.clock = steady_s;
    out_.reserve(1024);
    ev_.data.reserve(64 * 1024);
}

DeviceServer::~DeviceServer() { stop(); }

void DeviceServer::event(const std::string& line) {
    if (cfg_.on_event) cfg_.on_event(line);
}

void DeviceServer::drop(net::DropReason r) {
    malformed_.fetch_add(1, std::memory_order_relaxed);
    std::lock_guard lock(drops_mutex_);
    drops_.add(r);
}

net::DropCounts DeviceServer::drops() const {
    std::lock_guard lock(drops_mutex_);
    return drops_;
}

net::Header DeviceServer::header(std::uint32_t seq) const {
    net::Header h;
    h.version = cfg_.version;
    h.seq = seq;
    h.sent_us = static_cast<std::uint64_t>(std::llround(cfg_.clock() * 1e6)) + 1;
    h.echo_us = peer_sent_us_;
    return h;
}

DeviceServerStats DeviceServer::stats() const {
    DeviceServerStats s;
    s.ticks = ticks_.load(std::memory_order_relaxed);
    s.sessions = sessions_.load(std::memory_order_relaxed);
    s.refused = refused_.load(std::memory_order_relaxed);
    s.malformed = malformed_.load(std::memory_order_relaxed);
    s.lost = lost_.load(std::memory_order_relaxed);
    s.watchdog_trips = trips_.load(std::memory_order_relaxed);
    s.zeroed_ticks = zeroed_.load(std::memory_order_relaxed);
    s.stale_snapshots = stale_.load(std::memory_order_relaxed);
    s.snapshots = snapshots_.load(std::memory_order_relaxed);
    s.stale_force_ticks = stale_forces_.load(std::memory_order_relaxed);
    s.force_updates = force_updates_.load(std::memory_order_relaxed);
    s.device_lost = device_lost_.load(std::memory_order_relaxed);
    s.session = session_flag_.load(std::memory_order_relaxed);
    const devices::net::LinkTraffic traffic = link_.traffic();
    s.foreign = traffic.foreign;
    s.datagrams = traffic.datagrams;
    return s;
}

void DeviceServer::build_loop() {
    HapticLoopConfig c;
    c.period_s = cfg_.period_s;
    c.contact.stiffness_n_per_m = contact_.stiffness_n_per_m;
    c.contact.damping_n_s_per_m = contact_.damping_n_s_per_m;
    c.contact.tool_radius_m = contact_.tool_radius_m;
    c.contact.static_friction = contact_.static_friction;
    c.contact.dynamic_friction = std::min(contact_.dynamic_friction, contact_.static_friction);
    c.ewma_alpha = contact_.ewma_alpha;
    c.device_to_world = contact_.device_to_world;
    c.workspace_scale = contact_.workspace_scale;
    // The session's workspace moving, so that the HIP this loop sends is the one the session would map.
    if (contact_.workspace_mode > static_cast<std::uint8_t>(WorkspaceMode::kBubble)) {
        event("local rendering: the session's workspace mode " + std::to_string(contact_.workspace_mode) +
              " is not one this server knows; contact parameters refused");
        loop_.reset();
        return drop(net::DropReason::kOutOfRange);
    }
    c.workspace.mode = static_cast<WorkspaceMode>(contact_.workspace_mode);
    c.workspace.button_mask = contact_.button_mask;
    c.workspace.jump_gain = contact_.jump_gain;
    c.workspace.drag_gain = contact_.drag_gain;
    c.workspace.bubble_radius_m = contact_.bubble_radius_m;
    c.workspace.bubble_rate_m_s = contact_.bubble_rate_m_s;
    c.workspace.bubble_rate_exponent = contact_.bubble_rate_exponent;
    c.workspace.bubble_stiffness_n_per_m = contact_.bubble_stiffness_n_per_m;
    // The session's contact points (none: the single god-object of tool_radius_m), the wand's pair or an
    // interaction mesh.
    static_assert(net::kMaxContactPoints == kMaxToolPoints);
    c.tool_points.count = contact_.point_count;
    c.tool_points.radius_m = contact_.point_radius_m;
    c.tool_points.local_m = contact_.point_local_m;
    c.tool_points.normal = contact_.point_normal;
    c.contact_mode = c.tool_points.count > 2 ? MultiPointMode::kInteractionMesh : MultiPointMode::kIndependentProxies;
    c.request_realtime = false;
    if (!surface_) {
        surface_ = std::make_unique<TripleBuffer<ActiveSurface>>();
        samples_ = std::make_unique<SpscRing<ToolSample>>(4096);
    }
    loop_.reset();  // ends the previous loop's session (zero force, device disabled)
    try {
        loop_ = std::make_unique<HapticLoop>(device_, *surface_, *samples_, c);
    } catch (const Error& e) {
        event(std::string("local rendering: the session's contact parameters were refused: ") + e.what());
        drop(net::DropReason::kOutOfRange);
    }
}

void DeviceServer::pump(double now_s) {
    while (link_.poll(ev_)) {
        switch (ev_.kind) {
            case net::LinkEvent::kConnected:
                event(ev_.data.empty() ? std::string("a session connected")
                                       : "a session connected from " + std::string(ev_.data.begin(), ev_.data.end()));
                break;
            case net::LinkEvent::kDisconnected:
                if (session_) event("the session disconnected: force zeroed");
                session_ = false;
                session_flag_.store(false, std::memory_order_relaxed);
                break;
            case net::LinkEvent::kData: handle(ev_.data, now_s); break;
        }
    }
}

void DeviceServer::handle(const std::vector<std::uint8_t>& d, double now_s) {
    net::Header h;
    net::DropReason r = net::decode_header(d.data(), d.size(), h, cfg_.version);
    if (r == net::DropReason::kVersion && h.type == net::MsgType::kHello) {
        const std::string line = "net: the device server at " + std::string(link_.where()) + " speaks link version " +
                                 std::to_string(cfg_.version) + ", this session speaks " + std::to_string(h.version) +
                                 "; run the same tridex release on both machines";
        net::encode_refuse(header(0), line, out_);
        link_.send(out_, true);
        refused_.fetch_add(1, std::memory_order_relaxed);
        event("refused a session: " + line);
    }
    if (r != net::DropReason::kNone) return drop(r);
    if (h.type == net::MsgType::kHello) {
        net::Hello hello;
        if ((r = net::decode(d.data(), d.size(), hello)) != net::DropReason::kNone) return drop(r);
        session_ = true;
        session_flag_.store(true, std::memory_order_relaxed);
        mode_ = hello.mode;
        rx_seq_valid_ = false;
        force_ = {};
        last_rx_s_ = now_s;
        have_contact_ = false;
        loop_.reset();
        surface_seq_ = 0;
        cover_reach_m_ = -1.0;
        stale_forces_now_ = false;
        net::encode(header(++tx_seq_), net::welcome_from(device_.profile()), out_);
        link_.send(out_, true);
        sessions_.fetch_add(1, std::memory_order_relaxed);
        session_base_ = {lost_.load(std::memory_order_relaxed), malformed_.load(std::memory_order_relaxed),
                         stale_.load(std::memory_order_relaxed), trips_.load(std::memory_order_relaxed)};
        event(std::string("serving '") + device_.profile().name + "' in " + net::to_string(mode_) + " haptic rendering");
        return;
    }
    if (!session_) return drop(net::DropReason::kUnexpected);
    peer_sent_us_ = h.sent_us;
    // Force and heartbeat datagrams are one sequence (gaps are lost datagrams); snapshots and contact sets another.
    if (rx_seq_valid_ && static_cast<std::int32_t>(h.seq - rx_seq_) <= 0 && h.type != net::MsgType::kSurface &&
        h.type != net::MsgType::kContact)
        return;  // late: a newer one was applied
    switch (h.type) {
        case net::MsgType::kForce: {
            if (mode_ != net::RenderingMode::kDistributed) return drop(net::DropReason::kUnexpected);
            net::ForceMsg m;
            if ((r = net::decode(d.data(), d.size(), m)) != net::DropReason::kNone) return drop(r);
            force_ = m;
            force_updates_.fetch_add(1, std::memory_order_relaxed);
            break;
        }
        case net::MsgType::kHeartbeat:
            if (d.size() != net::kHeaderBytes) return drop(net::DropReason::kBadLength);
            break;
        case net::MsgType::kContact: {
            if (mode_ != net::RenderingMode::kLocal) return drop(net::DropReason::kUnexpected);
            net::ContactMsg m;
            if ((r = net::decode(d.data(), d.size(), m)) != net::DropReason::kNone) return drop(r);
            contact_ = m;
            have_contact_ = true;
            build_loop();
            break;
        }
        case net::MsgType::kSurface: {
            if (mode_ != net::RenderingMode::kLocal) return drop(net::DropReason::kUnexpected);
            if (!surface_) {
                surface_ = std::make_unique<TripleBuffer<ActiveSurface>>();
                samples_ = std::make_unique<SpscRing<ToolSample>>(4096);
            }
            ActiveSurface& back = surface_->back();
            if ((r = net::decode_surface(d.data(), d.size(), back)) != net::DropReason::kNone) return drop(r);
            snapshots_.fetch_add(1, std::memory_order_relaxed);
            if (back.sequence <= surface_seq_) {  // older than the one in use
                stale_.fetch_add(1, std::memory_order_relaxed);
                break;
            }
            // A snapshot is stale when the tool has already left the region its windows cover.
            const double reach = ActiveSurface::kCoverRays * back.window_spacing_cells(2) * back.cell_m;
            const Vec3 off = glm::abs(tool_world_m_ - back.centre_m);
            if (off.x > reach || off.y > reach || off.z > reach) stale_.fetch_add(1, std::memory_order_relaxed);
            surface_seq_ = back.sequence;
            cover_centre_m_ = back.centre_m;
            cover_reach_m_ = reach;
            surface_->publish();
            break;
        }
        default: return drop(net::DropReason::kUnexpected);
    }
    if (h.type == net::MsgType::kForce || h.type == net::MsgType::kHeartbeat) {
        if (rx_seq_valid_ && h.seq - rx_seq_ > 1) lost_.fetch_add(h.seq - rx_seq_ - 1, std::memory_order_relaxed);
        rx_seq_ = h.seq;
        rx_seq_valid_ = true;
    }
    last_rx_s_ = now_s;
}

void DeviceServer::send_state(const devices::DeviceState& s, const Vec3& applied_device_n, bool zeroed,
                              const devices::RemoteToolSample* tool) {
    if (!session_) return;
    net::StateMsg m;
    m.state = s;
    if (tool) {
        m.has_tool = true;
        m.tool = *tool;
    }
    m.applied_force_n = applied_device_n;
    m.watchdog_zeroed = zeroed;
    // This session's counts: since its kHello.
    m.lost = static_cast<std::uint32_t>(lost_.load(std::memory_order_relaxed) - session_base_.lost);
    m.malformed = static_cast<std::uint32_t>(malformed_.load(std::memory_order_relaxed) - session_base_.malformed);
    m.stale_snapshots = static_cast<std::uint32_t>(stale_.load(std::memory_order_relaxed) - session_base_.stale);
    m.watchdog_trips = static_cast<std::uint32_t>(trips_.load(std::memory_order_relaxed) - session_base_.trips);
    net::encode(header(++tx_seq_), m, out_);
    link_.send(out_, false);
}

bool DeviceServer::tick(double now_s) {
    if (device_lost_.load(std::memory_order_relaxed)) return false;
    if (device_.state() != devices::DeviceLifecycle::kEnabled && !loop_) device_.bring_up();
    pump(now_s);
    ticks_.fetch_add(1, std::memory_order_relaxed);
    if (!session_) {  // no session: the device rests at zero force and its clock is not run
        if (served_) device_.write(Vec3(0.0), Vec3(0.0));
        served_ = false;
        silent_ = false;
        return true;
    }
    served_ = true;
    const bool silent = now_s - last_rx_s_ > cfg_.watchdog_s;
    if (silent && !silent_) {
        trips_.fetch_add(1, std::memory_order_relaxed);
        event("no datagram from the session for " + std::to_string(static_cast<int>(std::lround(cfg_.watchdog_s * 1e3))) +
              " ms: force zeroed");
    }
    const bool went_silent = silent && !silent_;
    silent_ = silent;
    if (silent && !went_silent) {  // a silent session: zero force was written, the device rests until it speaks again
        zeroed_.fetch_add(1, std::memory_order_relaxed);
        return true;
    }
    if (!silent && mode_ == net::RenderingMode::kLocal && loop_) {
        loop_time_s_ = std::max(loop_time_s_ + 1e-9, now_s);
        const TickRecord rec = loop_->step(loop_time_s_);
        force_updates_.fetch_add(1, std::memory_order_relaxed);
        // The tool sample of this tick (none on an invalid sample: the tool holds where it was).
        ToolSample drained;
        bool sampled = false;
        while (samples_->try_pop(drained)) sampled = true;
        if (loop_->stats().device_lost) {
            device_lost_.store(true, std::memory_order_relaxed);
            event("the device is gone: serving stopped");
            return false;
        }
        tool_world_m_ = rec.hip_m;
        // A force rendered on a snapshot the tool has left is stale: counted, and logged when it begins.
        const Vec3 off = glm::abs(rec.hip_m - cover_centre_m_);
        const bool stale = cover_reach_m_ >= 0.0 && (off.x > cover_reach_m_ || off.y > cover_reach_m_ || off.z > cover_reach_m_);
        if (stale) {
            stale_forces_.fetch_add(1, std::memory_order_relaxed);
            if (!stale_forces_now_ && now_s - stale_logged_s_ >= 1.0) {
                stale_logged_s_ = now_s;
                event("local rendering: the tool left the newest snapshot's region: its forces are stale until a "
                      "newer snapshot arrives (" + std::to_string(stale_forces_.load(std::memory_order_relaxed)) +
                      " stale ticks so far)");
            }
        }
        stale_forces_now_ = stale;
        const Vec3 applied = glm::conjugate(contact_.device_to_world.orientation) * rec.force_n;
        devices::RemoteToolSample tool;
        tool.tool_world = sampled ? Pose{drained.position, drained.orientation} : rec.tool_world;
        tool.proxy_m = sampled ? drained.surface_m : rec.proxy_m;
        tool.force_n = rec.force_n;
        tool.contact = rec.contact;
        tool.hold = !sampled || drained.op == ToolOp::kNone;
        send_state(rec.device, applied, false, &tool);
        return true;
    }
    devices::DeviceState s;
    if (!device_.read(s)) {
        device_.write(Vec3(0.0), Vec3(0.0));
        device_lost_.store(true, std::memory_order_relaxed);
        event("the device is gone: serving stopped");
        return false;
    }
    const bool zero = silent || mode_ != net::RenderingMode::kDistributed;
    const Vec3 f = zero ? Vec3(0.0) : force_.force_n;
    device_.write(f, zero ? Vec3(0.0) : force_.torque_nm);
    if (zero) zeroed_.fetch_add(1, std::memory_order_relaxed);
    send_state(s, f, silent);
    return true;
}

void DeviceServer::start() {
    if (running()) return;
    if (thread_.joinable()) thread_.join();
    device_.bring_up();
    stop_requested_.store(false, std::memory_order_relaxed);
    running_.store(true, std::memory_order_release);
    thread_ = std::thread(&DeviceServer::run, this);
}

void DeviceServer::stop() {
    stop_requested_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    loop_.reset();
    try {
        device_.write(Vec3(0.0), Vec3(0.0));
    } catch (...) {
    }
    device_.disable();
}

void DeviceServer::run() noexcept {
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    name_this_thread("tridex-devserver");
    if (cfg_.request_realtime) {
        const RealtimeStatus rt = request_realtime(80, false);
        if (!rt.fifo) event("real-time scheduling refused: ticks may jitter");
    }
    const auto period_ns = static_cast<std::int64_t>(std::llround(cfg_.period_s * 1e9));
    std::int64_t next = monotonic_ns();
    try {
        while (!stop_requested_.load(std::memory_order_acquire)) {
            sleep_until_ns(next);
            if (!tick(cfg_.clock())) break;
            next += period_ns;
            const std::int64_t now = monotonic_ns();
            if (now >= next) next += ((now - next) / period_ns + 1) * period_ns;
        }
    } catch (const std::exception& e) {
        event(std::string("serving stopped: ") + e.what());
        device_lost_.store(true, std::memory_order_relaxed);
    }
    running_.store(false, std::memory_order_release);
}

}  // namespace tridex::haptics
