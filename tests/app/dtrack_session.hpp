// tests/app/dtrack_session.hpp - offscreen `tridex run` sessions driven by DTrack datagrams sent over UDP on loopback,
// as a wall's tracker sends them.
#pragma once

#include <atomic>
#include <chrono>
#include <filesystem>
#include <utility>
#include <thread>

#include "../devices/dtrack_sender.hpp"
#include "app/session/run/run_options.hpp"
#include "app/session/run/run_session.hpp"
#include "devices/tracking/dtrack_receiver.hpp"

namespace tridex::app::test {

/// A UDP port on 127.0.0.1 free a moment ago (a receiver bound to port 0 and closed).
inline int free_dtrack_port() {
    devices::DTrackReceiver probe(0, "127.0.0.1");
    return probe.port();
}

/// When a session became ready, seen from a sender's thread: the session's journal file appears once its workpiece,
/// device and threads are being set up, so a script timed from it does not depend on how long the machine took to
/// get there.
class SessionReady {
public:
    explicit SessionReady(std::filesystem::path journal) : journal_(std::move(journal)) {}
    /// Seconds since the journal appeared, as of sender time t_s; negative before (the script's hand waits at rest).
    double since(double t_s) {
        if (at_s_ < 0.0 && std::filesystem::exists(journal_)) at_s_ = t_s;
        return at_s_ < 0.0 ? -1.0 : t_s - at_s_;
    }

private:
    std::filesystem::path journal_;
    double at_s_ = -1.0;
};

/// Runs the session of `o` (run_stereo_session) while a thread sends `frame(tx, fr, t_s)` (fr = 1, 2, ...; t_s the
/// seconds since the sender started) to 127.0.0.1:port every 5 ms; the sender stops (and is joined) however the
/// session ends.
template <class Frame>
void run_while_sending(const RunOptions& o, int port, Frame frame) {
    std::atomic<bool> stop{false};
    std::thread sender([&] {
        tridex::test::DTrackSender tx(port);
        const auto t0 = std::chrono::steady_clock::now();
        for (unsigned fr = 1; !stop.load(); ++fr) {
            frame(tx, fr, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    });
    try {
        run_stereo_session(o);
    } catch (...) {
        stop = true;
        sender.join();
        throw;
    }
    stop = true;
    sender.join();
}

}  // namespace tridex::app::test
