// bench/bench_input.cpp - DTrack parse cost and receiver hand-off latency.
#include "bench/bench_input.hpp"
#include "bench/bench_registry.hpp"

#include <CLI/CLI.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "app/support/json_file.hpp"
#include "core/summary.hpp"
#include "core/error.hpp"
#include "devices/tracking/dtrack_parser.hpp"
#include "devices/tracking/dtrack_receiver.hpp"

namespace tridex::bench {
using namespace tridex::app;  // bench sits above app: sessions, stats and JSON files

namespace {

using Clock = std::chrono::steady_clock;

std::string body_block(int id, double x) {
    char buf[192];
    std::snprintf(buf, sizeof buf, "[%d 1.000][%.3f 1520.250 810.500 0.0000 0.0000 0.0000]"
                  "[0.998629535 0.000000000 -0.052335956 0.000000000 1.000000000 0.000000000 0.052335956 "
                  "0.000000000 0.998629535]", id, x);
    return buf;
}

std::string flystick_block(int id) {
    char buf[192];
    std::snprintf(buf, sizeof buf, "[%d 1.000 8 2][120.500 1100.250 700.000]"
                  "[1.000000000 0.000000000 0.000000000 0.000000000 1.000000000 0.000000000 0.000000000 "
                  "0.000000000 1.000000000][1 0.2500 -0.5000]", id);
    return buf;
}

// A datagram as DTrack sends it: frame counter, timestamp, calibrated bodies, `bodies` 6d bodies, `sticks` Flysticks.
std::string datagram(unsigned fr, int bodies, int sticks) {
    std::string d = "fr " + std::to_string(fr) + "\r\nts 43521." + std::to_string(100000 + fr % 900000) + "\r\n6dcal " +
                    std::to_string(bodies) + "\r\n6d " + std::to_string(bodies) + " ";
    for (int i = 0; i < bodies; ++i) d += (i ? " " : "") + body_block(i, 100.0 + 10.0 * i);
    d += "\r\n";
    if (sticks > 0) {
        d += "6df2 " + std::to_string(sticks) + " " + std::to_string(sticks) + " ";
        for (int i = 0; i < sticks; ++i) d += (i ? " " : "") + flystick_block(i);
        d += "\r\n";
    }
    return d;
}

InputParseRow time_parse(const std::string& name, const std::string& text) {
    constexpr int kPerRound = 20000, kRounds = 7;
    devices::DTrackFrame frame;
    if (!devices::parse_dtrack_datagram(text, frame).ok())
        throw Error("bench --input: the '" + name + "' datagram was rejected by the parser");
    std::vector<double> ns;
    for (int r = 0; r < kRounds; ++r) {
        const auto t0 = Clock::now();
        int ok = 0;
        for (int i = 0; i < kPerRound; ++i) ok += devices::parse_dtrack_datagram(text, frame).ok();
        const double dt = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
        if (ok != kPerRound) throw Error("bench --input: a parse failed");
        ns.push_back(dt / kPerRound);
    }
    InputParseRow row;
    row.datagram = name;
    row.bytes = static_cast<int>(text.size());
    row.ns_per_datagram = summarize(ns).median;
    row.mb_per_s = row.bytes / row.ns_per_datagram * 1e3;
    return row;
}

InputHandoffRow time_handoff() {
    constexpr int kDatagrams = 1000;
    devices::DTrackReceiver rx(0, "127.0.0.1");
    const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) throw Error("bench --input: cannot open a UDP socket");
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<std::uint16_t>(rx.port()));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    std::vector<double> us;
    for (int i = 1; i <= kDatagrams; ++i) {
        const std::string d = datagram(static_cast<unsigned>(i), 1, 1);
        const auto t0 = Clock::now();
        ::sendto(fd, d.data(), d.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
        for (;;) {  // the render thread's side: latest() until this datagram shows
            if (rx.latest().accepted >= static_cast<std::uint64_t>(i)) break;
            if (Clock::now() - t0 > std::chrono::seconds(5)) {
                ::close(fd);
                throw Error("bench --input: a datagram sent to 127.0.0.1:" + std::to_string(rx.port()) +
                            " did not arrive within 5 s");
            }
        }
        us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        std::this_thread::sleep_until(t0 + std::chrono::milliseconds(2));
    }
    ::close(fd);
    const Summary s = summarize(us);
    return InputHandoffRow{kDatagrams, s.median, s.p99, s.max};
}

}  // namespace

InputBenchResult run_input_bench(const std::string& out) {
    InputBenchResult r;
    r.parse.push_back(time_parse("head", datagram(1, 1, 0)));
    r.parse.push_back(time_parse("head+flystick", datagram(1, 1, 1)));
    r.parse.push_back(time_parse("wall", datagram(1, 10, 2)));
    r.handoff = time_handoff();
    std::printf("bench --input: DTrack ASCII parse (median of 7 rounds x 20000)\n");
    std::printf("  %-14s %6s %12s %10s\n", "datagram", "bytes", "ns/datagram", "MB/s");
    nlohmann::json rows = nlohmann::json::array();
    for (const InputParseRow& p : r.parse) {
        std::printf("  %-14s %6d %12.0f %10.1f\n", p.datagram.c_str(), p.bytes, p.ns_per_datagram, p.mb_per_s);
        rows.push_back({{"datagram", p.datagram}, {"bytes", p.bytes}, {"ns_per_datagram", p.ns_per_datagram},
                        {"mb_per_s", p.mb_per_s}});
    }
    const InputHandoffRow& h = r.handoff;
    std::printf("  receiver hand-off (send -> reader sees it, loopback, %d datagrams): median %.1f us, p99 %.1f us, "
                "max %.1f us\n", h.datagrams, h.median_us, h.p99_us, h.max_us);
    std::filesystem::create_directories(out);
    write_json_file((std::filesystem::path(out) / "input_bench.json").string(),
                    {{"parse", rows},
                     {"handoff", {{"datagrams", h.datagrams}, {"median_us", h.median_us}, {"p99_us", h.p99_us},
                                  {"max_us", h.max_us}}}});
    return r;
}

namespace {

BenchRun setup_input_bench(CLI::App&) {
    return [](const BenchCommon& c) { run_input_bench(c.out); };
}

const BenchmarkRegistration kRegistration{
    {"input",
     "Tracked input: DTrack ASCII parse cost per datagram and the receiver's hand-off latency over loopback "
     "(input_bench.json)",
     10, setup_input_bench}};

}  // namespace

}  // namespace tridex::bench
