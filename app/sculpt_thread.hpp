// app/sculpt_thread.hpp - the sculpt thread: tool samples in, Booleans, dirty-tile contouring,
// active-surface snapshots out (DESIGN.md, "three threads").
#pragma once

#include <atomic>
#include <exception>
#include <cstdint>
#include <thread>
#include <vector>

#include "compute/contour_dual.hpp"
#include "compute/tridexel.hpp"
#include "core/active_surface.hpp"
#include "core/spsc_ring.hpp"
#include "core/tool_sample.hpp"
#include "core/triple_buffer.hpp"

namespace tridex::app {

/// Counters of the sculpt thread, read after stop().
struct SculptStats {
    std::uint64_t samples = 0;           ///< tool samples drained from the ring
    std::uint64_t booleans = 0;          ///< swept-volume Booleans applied (one per segment)
    std::uint64_t rays_changed = 0;      ///< rays whose intervals changed, summed over Booleans
    std::uint64_t steps = 0;             ///< sculpt steps that changed the model
    std::uint64_t tiles_recontoured = 0; ///< dirty tiles re-contoured, summed over steps
    std::uint64_t publishes = 0;         ///< active-surface snapshots published
    std::vector<double> boolean_ms;      ///< per changing step: Booleans + active-surface publish, ms
    std::vector<double> contour_ms;      ///< per changing step: dirty-tile re-contouring, ms
};

/// Drains ToolSamples in order and applies the swept volume of each consecutive pair (a capsule for
/// the ball tool) to the model, re-contours only the dirty tiles, and publishes the active surface
/// around the newest tool position. The model is a pure function of the sample stream: batching
/// changes only when work happens, not the result.
class SculptThread {
public:
    /// All references must outlive the thread. The initial snapshot is published centred on start_m
    /// (world m; throws tridex::Error when it is not finite).
    SculptThread(compute::TriDexel& model, compute::Contourer& contourer, SpscRing<ToolSample>& samples,
                 TripleBuffer<ActiveSurface>& surface, const Vec3& start_m);
    ~SculptThread();
    SculptThread(const SculptThread&) = delete;
    SculptThread& operator=(const SculptThread&) = delete;

    /// Starts the thread. Throws tridex::Error when it is already running.
    void start();
    /// Processes every sample still in the ring, then joins; call it after the producer (the haptic
    /// loop) has stopped. Idempotent. Rethrows the first exception the thread hit (a bad sample, out
    /// of memory); after such a failure the thread kept draining the ring without applying anything.
    void stop();
    /// Counters; call after stop().
    const SculptStats& stats() const { return stats_; }

private:
    void run();
    bool step();  // one drain + apply + contour + publish; false when there was nothing to do
    void publish(const Vec3& centre_m);

    compute::TriDexel& model_;
    compute::Contourer& contourer_;
    SpscRing<ToolSample>& samples_;
    TripleBuffer<ActiveSurface>& surface_;
    bool have_prev_ = false;
    ToolSample prev_{};
    Vec3 published_centre_m_;
    std::uint64_t sequence_ = 0;
    SculptStats stats_;
    std::atomic<bool> stop_{false};
    std::exception_ptr failure_;  // first exception on the thread, rethrown by stop()
    std::thread thread_;
};

}  // namespace tridex::app
