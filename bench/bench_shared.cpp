// bench/bench_shared.cpp - `tridex bench --shared`: a shared session's host and one joiner in this process, joined by
// the link shim at several one-way delays with loss, each carving its own groove at 1 kHz at once: how long after a
// sample its cut is contoured and ready to draw at each site (own and other's), bytes per second, digests.
#include "bench/bench_shared.hpp"

#include "bench/bench_registry.hpp"
#include "bench/bench_shared_sites.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/session/shared/shared_host.hpp"
#include "app/session/shared/shared_join.hpp"
#include "app/session/shared/shared_site.hpp"
#include "app/support/json_file.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/duration_histogram.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "devices/net/link_shim.hpp"

namespace tridex::bench {
namespace {

namespace fs = std::filesystem;
namespace net = devices::net;
using namespace shared_sites;

// The latencies of one site's publishes whose oldest cutting sample has a device time in [from_s, to_s): publish time
// minus the sample's push time (`pushed`, by device time in ms).
void latencies(const BenchSite& s, const std::vector<double>& pushed, double from_s, double to_s, DurationHistogram& out) {
    for (const auto& [published, t] : s.seen) {
        if (!(t >= from_s && t < to_s)) continue;
        const long i = std::lround(t * 1e3);
        if (i < 0 || i >= static_cast<long>(pushed.size()) || pushed[static_cast<std::size_t>(i)] <= 0.0) continue;
        out.add(1e3 * (published - pushed[static_cast<std::size_t>(i)]));
    }
}

void settle(BenchSite& hs, BenchSite& js, double delay_ms) {
    for (int k = 0; k < 500 + static_cast<int>(4 * delay_ms); ++k) {  // a few round trips
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        hs.take();
        js.take();
    }
}

SharedBenchRow run_row(const SharedBenchOptions& o, double delay_ms, const fs::path& dir) {
    if (o.stroke_s > 90.0) throw Error("--shared-stroke-s: at most 90 s");
    SharedBenchRow row;
    row.delay_ms = delay_ms;
    const double t0 = now_s();
    net::ShimConfig cfg;
    cfg.latency_s = delay_ms / 1e3;
    cfg.loss = o.loss;
    net::LinkShim shim(cfg, [t0] { return now_s() - t0; });
    std::unique_ptr<net::DatagramLink> server_end = shim.server_end();
    const net::SessionKey key = bench_key();
    app::SharedHostOptions ho;
    ho.key = key;
    ho.out = (dir / "host").string();
    fs::create_directories(ho.out);
    app::SharedHost host(ho, [&server_end]() { return std::move(server_end); });
    const compute::TriDexel m = bench_box(o.resolution);
    BenchSite hs(m);
    start_host_site(host, hs, m);
    app::SharedJoinOptions jo;
    jo.out = (dir / "join").string();
    app::SharedJoin join(jo, shim.client_end(), key);
    const std::unique_ptr<BenchSite> joiner = join_site(join);
    BenchSite& js = *joiner;

    // Device times tell the phases apart: [0, 100) s the host's and [100, 200) the joiner's grooves carved at once,
    // [200, 300) the joiner alone, [300, 400) the host alone.
    const int n = static_cast<int>(o.stroke_s * 1e3);
    std::vector<double> pushed(static_cast<std::size_t>(400e3), 0.0);
    const double begun = now_s();
    carve(hs, groove(0.02, 0.0, n), js, groove(-0.02, 100.0, n), pushed);
    settle(hs, js, delay_ms);
    carve(hs, {}, js, groove(-0.035, 200.0, n), pushed);
    settle(hs, js, delay_ms);
    carve(hs, groove(0.035, 300.0, n), js, {}, pushed);
    settle(hs, js, delay_ms);
    const double carved_s = now_s() - begun;
    hs.thread->stop();
    host.finish(hs.model);
    for (int k = 0; k < 20000 && join.ended().empty(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    js.thread->stop();
    join.finish(js.model);
    latencies(hs, pushed, 300.0, 400.0, row.own_host);
    latencies(js, pushed, 200.0, 300.0, row.own_join);
    latencies(hs, pushed, 200.0, 300.0, row.other_at_host);
    latencies(js, pushed, 300.0, 400.0, row.other_at_join);
    const nlohmann::json jr = join.report();
    row.join_out_bps = jr.value("bytes_out", 0.0) / carved_s;
    row.host_out_bps = jr.value("bytes_in", 0.0) / carved_s;
    row.digests_equal = compute::model_digest(js.model) == compute::model_digest(hs.model) && jr.value("digest_match", false);
    row.lost = shim.stats().lost;
    return row;
}

}  // namespace

std::vector<SharedBenchRow> run_shared_bench(const SharedBenchOptions& o) {
    if (!(o.loss >= 0.0 && o.loss < 0.5)) throw Error("--shared-loss: must be in [0, 0.5)");
    if (!(o.stroke_s >= 0.2 && o.stroke_s <= 60.0)) throw Error("--shared-stroke-s: must be in [0.2, 60] s");
    std::vector<SharedBenchRow> out;
    const fs::path dir = fs::path(o.out) / "shared";
    fs::create_directories(dir);
    std::printf("tridex bench --shared: host and one joiner in this process over the link shim, loss %.1f %%, each "
                "carving a %.1f s groove at 1 kHz at once, box at %d cells\n",
                100.0 * o.loss, o.stroke_s, o.resolution);
    std::printf("latency = the sample pushed into its site's ring -> a mesh holding its cut published at a site "
                "(contoured, ready to draw; the frame that draws it adds up to one frame). Own and other's cuts are\n"
                "timed while one site carves alone; bytes per second and digests cover the whole run, both carving at "
                "once first\n");
    std::printf("%9s | %21s | %21s | %21s | %21s | %10s %10s | %s\n", "delay ms", "host own cut ms", "joiner own cut ms",
                "joiner's cut at host", "host's cut at joiner", "host B/s", "joiner B/s", "digests");
    std::printf("%9s | %10s %10s | %10s %10s | %10s %10s | %10s %10s |\n", "", "median", "p99", "median", "p99", "median",
                "p99", "median", "p99");
    nlohmann::json rows = nlohmann::json::array();
    for (const double d : o.delays_ms) {
        if (!(d >= 0.0 && d <= 1000.0)) throw Error("--shared-delays-ms: each must be in [0, 1000]");
        const SharedBenchRow& r = out.emplace_back(run_row(o, d, dir / ("delay_" + std::to_string(static_cast<int>(d)))));
        const auto cell = [](const DurationHistogram& h) {
            char b[64];
            if (h.count() == 0) std::snprintf(b, sizeof b, "%21s", "no timed sample");
            else std::snprintf(b, sizeof b, "%10.1f %10.1f", h.percentile_ms(0.5), h.percentile_ms(0.99));
            return std::string(b);
        };
        std::printf("%9.0f | %21s | %21s | %21s | %21s | %10.0f %10.0f | %s\n", d, cell(r.own_host).c_str(),
                    cell(r.own_join).c_str(), cell(r.other_at_host).c_str(), cell(r.other_at_join).c_str(), r.host_out_bps,
                    r.join_out_bps, r.digests_equal ? "equal" : "DIFFER");
        const auto js = [](const DurationHistogram& h) {
            return nlohmann::json{{"count", h.count()},
                                  {"median_ms", h.count() ? nlohmann::json(h.percentile_ms(0.5)) : nlohmann::json(nullptr)},
                                  {"p99_ms", h.count() ? nlohmann::json(h.percentile_ms(0.99)) : nlohmann::json(nullptr)}};
        };
        rows.push_back({{"delay_ms", d}, {"loss", o.loss}, {"host_own_cut", js(r.own_host)}, {"joiner_own_cut", js(r.own_join)},
                        {"joiner_cut_at_host", js(r.other_at_host)}, {"host_cut_at_joiner", js(r.other_at_join)},
                        {"host_to_joiner_bytes_per_s", r.host_out_bps}, {"joiner_to_host_bytes_per_s", r.join_out_bps},
                        {"digests_equal", r.digests_equal}, {"unreliable_lost", r.lost}});
    }
    app::write_json_file((fs::path(o.out) / "shared_bench.json").string(), {{"rows", rows}, {"resolution", o.resolution},
                                                                            {"stroke_s", o.stroke_s}});
    return out;
}

namespace {

BenchRun setup_shared(CLI::App& bench) {
    auto o = std::make_shared<SharedBenchOptions>();
    bench.add_option("--shared-delays-ms", o->delays_ms, "With --shared: one-way delays, ms (default 0 10 50 150)");
    bench.add_option("--shared-loss", o->loss, "With --shared: loss of unreliable datagrams (default 0.01)");
    bench.add_option("--shared-stroke-s", o->stroke_s, "With --shared: each groove's length, s (default 2)");
    bench.add_option("--shared-join-minutes", o->join_minutes,
                     "With --shared: late joins after these minutes of sculpting, 1..60 (default 1 10)");
    bench.add_option("--shared-resolution", o->resolution, "With --shared: the box's cells along a side (default 96)");
    bench.add_option("--shared-flood-s", o->flood_s,
                     "With --shared: each phase of the haptic period's run over ENet, quiet then flooded, s (default 5; "
                     "0 skips it)");
    return [o](const BenchCommon& c) {
        SharedBenchOptions run = *o;
        run.out = c.out;
        (void)run_shared_bench(run);
        (void)run_shared_flood_bench(run);
        (void)run_late_join_bench(run);
    };
}

const BenchmarkRegistration kRegistration{
    {"shared",
     "A shared session's host and joiner over the link shim at several delays with loss: own and other's cut ready "
     "to draw after the sample, bytes per second, digests; then the host's haptic period over ENet, quiet and while "
     "random datagrams flood its port",
     49, setup_shared}};

}  // namespace
}  // namespace tridex::bench
