// bench/bench_shared_flood.cpp - `tridex bench --shared`'s flood run: the host's haptic period while random datagrams
// flood its port. A shared session over real ENet on the loopback (an EnetHub feeding a SharedHost, one SharedJoin
// connected with EnetLink, sealed with one key, as `tridex run --host` and `--join` build them), a 1 kHz haptic loop
// on a simulated device carving at the host, the joiner carving a groove; once quiet, once flooded from another
// socket, with cyclictest beside each phase for the machine's own wake-up latency.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/session/shared/shared_host.hpp"
#include "app/session/shared/shared_join.hpp"
#include "app/session/shared/shared_site.hpp"
#include "app/support/json_file.hpp"
#include "bench/bench_shared.hpp"
#include "bench/bench_shared_sites.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/model/tdx_file.hpp"
#include "core/error.hpp"
#include "devices/net/enet_hub.hpp"
#include "devices/net/enet_link.hpp"
#include "devices/simulated_device.hpp"
#include "haptics/haptic_loop.hpp"

namespace tridex::bench {
namespace {

namespace fs = std::filesystem;
namespace net = devices::net;
using namespace shared_sites;

// How long a silent peer is kept, s: as `tridex run --host` and `--join` keep it.
constexpr double kPeerTimeoutS = 5.0;
// The largest flood datagram, bytes (below the loopback's and a LAN's MTU, as a real flood's would be).
constexpr std::size_t kMaxFloodBytes = 1200;

// Random datagrams of 1..kMaxFloodBytes bytes sent to 127.0.0.1:port from a socket of its own, as fast as sendto()
// returns, on a thread of its own from construction until stop() (or destruction, which stops and joins it).
class FloodSender {
public:
    // Throws tridex::Error when the socket cannot be opened.
    FloodSender(std::uint16_t port, std::uint32_t seed) : fd_(::socket(AF_INET, SOCK_DGRAM, 0)) {
        if (fd_ < 0) throw Error(std::string("bench --shared: cannot open the flood's socket: ") + std::strerror(errno));
        to_.sin_family = AF_INET;
        to_.sin_port = htons(port);
        to_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        thread_ = std::thread([this, seed] { run(seed); });
    }
    ~FloodSender() {
        stop();
        ::close(fd_);
    }
    FloodSender(const FloodSender&) = delete;
    FloodSender& operator=(const FloodSender&) = delete;
    // Stops sending and joins the thread; idempotent.
    void stop() {
        stop_.store(true);
        if (thread_.joinable()) thread_.join();
    }
    std::uint64_t sent() const { return sent_.load(); }
    std::uint64_t failed() const { return failed_.load(); }

private:
    void run(std::uint32_t seed) {
        std::mt19937_64 rng(seed);
        std::uniform_int_distribution<std::size_t> length(1, kMaxFloodBytes);
        std::uint64_t buf[kMaxFloodBytes / 8];
        while (!stop_.load(std::memory_order_relaxed)) {
            for (std::uint64_t& w : buf) w = rng();  // fresh bytes every datagram, so none repeats
            const std::size_t n = length(rng);
            if (::sendto(fd_, buf, n, 0, reinterpret_cast<const sockaddr*>(&to_), sizeof to_) == static_cast<ssize_t>(n))
                sent_.fetch_add(1, std::memory_order_relaxed);
            else
                failed_.fetch_add(1, std::memory_order_relaxed);
        }
    }
    int fd_;
    sockaddr_in to_{};
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> sent_{0}, failed_{0};
    std::thread thread_;
};

// True when an executable `name` is on PATH.
bool on_path(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "");
    for (std::string d; std::getline(dirs, d, ':');)
        if (!d.empty() && ::access((fs::path(d) / name).c_str(), X_OK) == 0) return true;
    return false;
}

// cyclictest beside a phase: one SCHED_OTHER thread waking every 1 ms for `seconds` (no real-time priority and no
// /dev/cpu_dma_latency, as the haptic loop here runs), on a thread of its own; max_ms() joins it and gives its
// largest wake-up latency, ms, or < 0 when cyclictest is not on PATH or printed no figure. Destruction joins.
class Cyclictest {
public:
    explicit Cyclictest(double seconds) {
        if (!on_path("cyclictest")) return;
        const std::string cmd = "cyclictest -t1 --policy=normal --laptop -i 1000 -D " +
                                std::to_string(static_cast<int>(std::ceil(seconds))) + " -q 2>/dev/null";
        thread_ = std::thread([this, cmd] {
            if (FILE* p = ::popen(cmd.c_str(), "r")) {
                char line[512];
                while (std::fgets(line, sizeof line, p))
                    if (const char* m = std::strstr(line, "Max:")) max_us_ = std::strtod(m + 4, nullptr);
                ::pclose(p);
            }
        });
    }
    ~Cyclictest() {
        if (thread_.joinable()) thread_.join();
    }
    Cyclictest(const Cyclictest&) = delete;
    Cyclictest& operator=(const Cyclictest&) = delete;
    double max_ms() {
        if (thread_.joinable()) thread_.join();
        return max_us_ >= 0.0 ? max_us_ / 1e3 : -1.0;
    }

private:
    std::thread thread_;
    double max_us_ = -1.0;
};

// Datagrams the kernel dropped at the UDP socket bound to 127.0.0.1:port (/proc/net/udp's last column); 0 when it
// is not listed.
std::uint64_t kernel_drops(std::uint16_t port) {
    std::ifstream f("/proc/net/udp");
    char want[16];
    std::snprintf(want, sizeof want, "0100007F:%04X", static_cast<unsigned>(port));
    for (std::string line; std::getline(f, line);) {
        std::istringstream in(line);
        std::string slot, local, last, field;
        in >> slot >> local;
        if (local != want) continue;
        while (in >> field) last = field;
        return std::strtoull(last.c_str(), nullptr, 10);
    }
    return 0;
}

// The host's hand: from 11 mm above the box's top face down to 2.7 mm into it, then back and forth along x over
// 60 mm each second while creeping across y, for `seconds` of device time; then it holds.
devices::ScriptedPath raster(double seconds) {
    std::vector<double> t{0.0, 0.3};
    std::vector<Vec3> p{Vec3(-0.03, 0.03, 0.06), Vec3(-0.03, 0.03, 0.046)};
    for (int k = 1; 0.3 + k <= seconds + 1.0; ++k) {
        t.push_back(0.3 + k);
        p.push_back(Vec3(k % 2 ? 0.03 : -0.03, 0.03 - 0.025 * (k / (seconds + 1.0)), 0.046));
    }
    return devices::ScriptedPath(std::move(t), std::move(p));
}

// The haptic loop as the session's, on a simulated device carving with a ball of 4 mm; no real-time scheduling, as
// a session run by someone without the privilege gets.
haptics::HapticLoopConfig loop_config() {
    haptics::HapticLoopConfig cfg;
    cfg.contact.tool_radius_m = 0.004;
    cfg.op = ToolOp::kSubtract;
    cfg.request_realtime = false;
    return cfg;
}

// The haptic loop's figures of a phase into `row`.
void take_loop_stats(const haptics::LoopStats& st, SharedFloodRow& row) {
    row.ticks = st.ticks;
    row.period_p99_ms = 1e3 * st.period_histogram.quantile(0.99);
    row.worst_ms = 1e3 * st.period_histogram.max_s;
    row.over_5ms = st.periods_over_5ms;
    row.overruns = st.overruns;
    row.samples_dropped = st.samples_dropped;
}

// One phase: a fresh session, the haptic loop and the joiner's groove for o.flood_s, flooded or not, then both
// sites finish and their digests are compared.
SharedFloodRow run_phase(const SharedBenchOptions& o, bool flood, const fs::path& dir) {
    SharedFloodRow row;
    row.phase = flood ? "flood" : "quiet";
    const net::SessionKey key = bench_key();
    std::shared_ptr<net::EnetHub> hub = net::EnetHub::listen("127.0.0.1", 0, kMaxSites - 1, kPeerTimeoutS);
    const std::uint16_t port = hub->port();
    app::SharedHostOptions ho;
    ho.key = key;
    ho.out = (dir / "host").string();
    fs::create_directories(ho.out);
    app::SharedHost host(ho, [hub] { return hub->accept(); });
    const compute::TriDexel m = bench_box(o.resolution);
    const std::uint64_t start_digest = compute::model_digest(m);
    BenchSite hs(m);
    start_host_site(host, hs, m);
    app::SharedJoinOptions jo;
    jo.out = (dir / "join").string();
    app::SharedJoin join(jo, net::EnetLink::connect("127.0.0.1", port, kPeerTimeoutS), key);
    const std::unique_ptr<BenchSite> joiner = join_site(join);
    BenchSite& js = *joiner;

    devices::SimulatedDevice device(devices::DeviceProfile::phantom_omni(), raster(o.flood_s));
    haptics::HapticLoop loop(device, hs.surface, hs.ring, loop_config());
    const int n = static_cast<int>(o.flood_s * 1e3);
    std::vector<double> pushed(static_cast<std::size_t>(n) + 2, 0.0);
    const net::LinkTraffic traffic0 = hub->traffic();
    const std::uint64_t drops0 = kernel_drops(port);
    {
        Cyclictest cyclictest(o.flood_s);
        std::unique_ptr<FloodSender> sender = flood ? std::make_unique<FloodSender>(port, 20261128u) : nullptr;
        const double begun = now_s();
        loop.start();
        carve(hs, {}, js, groove(-0.02, 0.0, n), pushed);  // the joiner's hand paces the phase
        loop.stop();
        row.seconds = now_s() - begun;
        if (sender) {
            sender->stop();
            row.flooded = sender->sent();
        }
        const double ct = cyclictest.max_ms();
        row.cyclictest_ran = ct >= 0.0;
        row.cyclictest_max_ms = row.cyclictest_ran ? ct : 0.0;
    }
    take_loop_stats(loop.stats(), row);
    const net::LinkTraffic traffic1 = hub->traffic();
    row.hub_datagrams = traffic1.datagrams - traffic0.datagrams;
    row.hub_foreign = traffic1.foreign - traffic0.foreign;
    row.kernel_drops = kernel_drops(port) - drops0;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the last records reach the joiner

    hs.thread->stop();
    host.finish(hs.model);
    for (int k = 0; k < 20000 && join.ended().empty(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    js.thread->stop();
    join.finish(js.model);
    const nlohmann::json jr = join.report(), hr = host.report();
    for (const app::JoinerReport& r : host.joiners()) row.sealed_refused += r.sealed_refused;
    row.sealed_refused += jr.value("sealed_refused", std::uint64_t{0});
    row.peers_refused = hr.value("peers_refused", std::uint64_t{0});
    row.hub_refused = hub->stats().refused;  // the host's network thread has stopped: this thread may read them
    const std::uint64_t host_digest = compute::model_digest(hs.model);
    row.digests_equal = compute::model_digest(js.model) == host_digest && jr.value("digest_match", false);
    row.carved = host_digest != start_digest;
    return row;
}

std::string ms_cell(bool have, double ms) {
    char b[32];
    if (have) std::snprintf(b, sizeof b, "%.2f", ms);
    else std::snprintf(b, sizeof b, "%s", "no figure");
    return b;
}

void print_row(const SharedFloodRow& r, bool cyclictest_found) {
    const std::string ct = cyclictest_found ? ms_cell(r.cyclictest_ran, r.cyclictest_max_ms) : "not on PATH";
    char haptic[64];
    if (r.ticks == 0) std::snprintf(haptic, sizeof haptic, "%31s", "no timed sample");
    else std::snprintf(haptic, sizeof haptic, "%9.2f %9.2f %11zu", r.period_p99_ms, r.worst_ms, r.over_5ms);
    std::printf("%6s | %12zu | %s | %17s | %9llu | %9llu | %12llu | %s\n", r.phase.c_str(), r.ticks, haptic, ct.c_str(),
                static_cast<unsigned long long>(r.flooded), static_cast<unsigned long long>(r.hub_foreign + r.sealed_refused),
                static_cast<unsigned long long>(r.kernel_drops), r.digests_equal ? "equal" : "DIFFER");
}

nlohmann::json row_json(const SharedFloodRow& r) {
    const auto timed = [&r](double v) { return r.ticks ? nlohmann::json(v) : nlohmann::json(nullptr); };
    return {{"phase", r.phase}, {"seconds", r.seconds}, {"haptic_ticks", r.ticks},
            {"period_p99_ms", timed(r.period_p99_ms)}, {"worst_period_ms", timed(r.worst_ms)},
            {"periods_over_5ms", r.over_5ms}, {"overruns", r.overruns}, {"haptic_samples_dropped", r.samples_dropped},
            {"cyclictest_max_ms", r.cyclictest_ran ? nlohmann::json(r.cyclictest_max_ms) : nlohmann::json(nullptr)},
            {"datagrams_flooded", r.flooded}, {"hub_datagrams", r.hub_datagrams},
            {"hub_from_no_peer", r.hub_foreign}, {"sealed_refused", r.sealed_refused},
            {"refused", r.hub_foreign + r.sealed_refused}, {"kernel_drops", r.kernel_drops},
            {"peers_refused", r.peers_refused}, {"hub_connects_refused", r.hub_refused},
            {"digests_equal", r.digests_equal}, {"host_carved", r.carved}};
}

}  // namespace

std::vector<SharedFloodRow> run_shared_flood_bench(const SharedBenchOptions& o) {
    std::vector<SharedFloodRow> rows;
    if (o.flood_s == 0.0) {
        std::printf("haptic period while the link floods: skipped (--shared-flood-s 0)\n");
        return rows;
    }
    if (!(o.flood_s >= 0.5 && o.flood_s <= 600.0)) throw Error("--shared-flood-s: must be 0 (skip) or in [0.5, 600] s");
    const fs::path dir = fs::path(o.out) / "shared_flood";
    fs::create_directories(dir);
    const bool cyclictest_found = on_path("cyclictest");
    std::printf("haptic period while the link floods: host and one joiner over ENet on 127.0.0.1 (sealed), a 1 kHz "
                "haptic loop (no real-time priority) on a simulated hand carving at the host, the joiner carving a "
                "groove;\n%.1f s quiet, then %.1f s with random datagrams of 1..%zu bytes sent at the host's port as "
                "fast as a socket sends them. refused = from no peer of the hub (ENet discards them) + refused by the "
                "sealed links;\nkernel drops = dropped at the host's socket, its buffer full. cyclictest: one "
                "SCHED_OTHER thread waking every 1 ms beside the phase (%s)\n",
                o.flood_s, o.flood_s, kMaxFloodBytes, cyclictest_found ? "on PATH" : "not on PATH: no figure");
    std::printf("%6s | %12s | %9s %9s %11s | %17s | %9s | %9s | %12s | %s\n", "phase", "haptic ticks", "p99 ms",
                "worst ms", "over 5 ms", "cyclictest max ms", "flooded", "refused", "kernel drops", "digests");
    nlohmann::json js = nlohmann::json::array();
    for (const bool flood : {false, true}) {
        rows.push_back(run_phase(o, flood, dir / (flood ? "flood" : "quiet")));
        print_row(rows.back(), cyclictest_found);
        js.push_back(row_json(rows.back()));
    }
    app::write_json_file((fs::path(o.out) / "shared_flood.json").string(),
                         {{"rows", js}, {"phase_s", o.flood_s}, {"resolution", o.resolution},
                          {"cyclictest_on_path", cyclictest_found}, {"max_flood_datagram_bytes", kMaxFloodBytes}});
    return rows;
}

}  // namespace tridex::bench
