// compute/runtime/site_intake.hpp - what other sites of a shared session hand the sculpt thread: their tool samples
// and their undo, redo and stroke-close requests, in the order a network thread received them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <span>
#include <vector>

#include "core/tool_sample.hpp"

namespace tridex::app {

/// A request to the sculpt thread (SculptThread::request, SiteIntake::push_request).
enum class SculptRequest : std::uint8_t {
    kUndo,       ///< undo the newest stroke (the open one is closed first)
    kRedo,       ///< redo the newest undone stroke
    kEndStroke,  ///< close the open stroke (e.g. the stylus button was released)
    kSave,       ///< save the model now with the saver (SculptThread::use_saver)
};

/// One entry of a SiteIntake: a tool sample (its site in sample.site), or a request of `site`.
struct SiteEntry {
    bool is_request = false;
    ToolSample sample{};                              ///< !is_request: the sample
    SculptRequest request = SculptRequest::kEndStroke;  ///< is_request: kUndo, kRedo or kEndStroke
    std::uint8_t site = 0;                            ///< is_request: whose request (0..kMaxSites-1)
};

/// A queue of other sites' samples and requests for the sculpt thread (SculptThread::use_site_intake), in arrival
/// order: a site's request is taken after the samples it sent before it. Any number of threads may push; the sculpt
/// thread drains. A mutex guards it (the haptic loop never touches it: its own samples go through a lock-free ring).
class SiteIntake {
public:
    /// Most entries held: a push that would exceed it drops the newest entries and counts them (dropped()), so a
    /// sculpt thread that cannot keep up never grows memory without bound. 30 s of one 1 kHz site.
    static constexpr std::size_t kMaxEntries = 30'000;
    /// Queues `samples` in order. Throws tridex::Error, queuing none of them, when a sample's site is 0 (the session's
    /// own tool, whose samples come from its haptic loop) or >= kMaxSites.
    void push_samples(std::span<const ToolSample> samples);
    /// Queues a request of `site`. Throws tridex::Error when site is 0 or >= kMaxSites, or r is kSave (a remote site
    /// does not save the host's model).
    void push_request(std::uint8_t site, SculptRequest r);
    /// Moves every queued entry to the end of `out`, in order; returns how many.
    std::size_t drain(std::vector<SiteEntry>& out);
    /// Entries queued now.
    std::size_t pending() const;
    /// Entries dropped because the queue was full.
    std::uint64_t dropped() const;

private:
    mutable std::mutex mutex_;
    std::deque<SiteEntry> queue_;
    std::uint64_t dropped_ = 0;
};

}  // namespace tridex::app
