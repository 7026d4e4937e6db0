// compute/runtime/site_intake.hpp - what other sites of a shared session hand the sculpt thread: their tool samples
// and their undo, redo and stroke-close requests, in the order a network thread received them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <span>
#include <vector>

#include "compute/journal/journal_reader.hpp"
#include "core/tool_sample.hpp"

namespace tridex::app {

/// A request to the sculpt thread (SculptThread::request, SiteIntake::push_request).
enum class SculptRequest : std::uint8_t {
    kUndo,       ///< undo the newest stroke (the open one is closed first)
    kRedo,       ///< redo the newest undone stroke
    kEndStroke,  ///< close the open stroke (e.g. the stylus button was released)
    kSave,       ///< save the model now with the saver (SculptThread::use_saver)
    kFiner,      ///< the model's coarseness halved: re-sampled onto a lattice of twice the resolution (an undo step)
    kCoarser,    ///< the model's coarseness doubled: re-sampled onto a lattice of half the resolution (an undo step)
};

/// The request's name in messages: "undo", "redo", "stroke close", "save", "finer" or "coarser".
inline const char* sculpt_request_name(SculptRequest r) {
    switch (r) {
        case SculptRequest::kUndo: return "undo";
        case SculptRequest::kRedo: return "redo";
        case SculptRequest::kEndStroke: return "stroke close";
        case SculptRequest::kSave: return "save";
        case SculptRequest::kFiner: return "finer";
        case SculptRequest::kCoarser: return "coarser";
    }
    return "request";
}

/// One entry of a SiteIntake: a tool sample (its site in sample.site), a request of `site` (the host's intake), or a
/// mark of the host's stream (a follower's intake: journal_format.hpp's kJournalStrokeEnd, kJournalUndo, kJournalRedo),
/// or the host's digest to check against (kCheck).
struct SiteEntry {
    enum Kind : std::uint8_t { kSample, kRequest, kMark, kCheck, kSnapshot };
    Kind kind = kSample;
    ToolSample sample{};                              ///< kSample: the sample
    SculptRequest request = SculptRequest::kEndStroke;  ///< kRequest: kUndo, kRedo or kEndStroke
    std::uint8_t site = 0;                            ///< kRequest: whose request; kSnapshot: who joins (0..kMaxSites-1)
    std::uint32_t mark = 0;                           ///< kMark: its journal record type
    std::uint64_t serial = 0;                         ///< kMark: the stroke's serial; kCheck: the host's digest
    std::uint64_t rays = 0;                           ///< kMark: undo, redo: rays written back
};

/// A queue of other sites' samples and requests for the sculpt thread (SculptThread::use_site_intake), in arrival
/// order: a site's request is taken after the samples it sent before it. Any number of threads may push; the sculpt
/// thread drains. A mutex guards it (the haptic loop never touches it: its own samples go through a lock-free ring).
class SiteIntake {
public:
    /// Most entries held: a push that would exceed it drops the newest entries and counts them (dropped()), so a
    /// sculpt thread that cannot keep up never grows memory without bound. 30 s of one 1 kHz site.
    static constexpr std::size_t kMaxEntries = 30'000;
    /// Queues `samples` in order; a sample without a time of this machine's clock (made_s NaN: it came over the
    /// network) gets its arrival, steady-clock s, so latency figures run from there. Throws tridex::Error, queuing none of them, when a sample's site is 0 (the session's
    /// own tool, whose samples come from its haptic loop) or >= kMaxSites.
    void push_samples(std::span<const ToolSample> samples);
    /// Queues a request of `site`. Throws tridex::Error when site is 0 or >= kMaxSites, or r is kSave (a remote site
    /// does not save the host's model).
    void push_request(std::uint8_t site, SculptRequest r);
    /// A follower (SculptThread::follow_host): queues the host's stream, one batch of samples (any site) or one mark
    /// (type kJournalStrokeEnd, kJournalUndo or kJournalRedo of journal_format.hpp) at a time, in the host's order.
    /// Samples get their arrival as made_s, as push_samples gives it.
    /// Throws tridex::Error, queuing nothing, for a sample of a site >= kMaxSites or another mark type. Never drops:
    /// the stream is the model, so a follower that fell behind holds it all (the host's pace bounds it).
    void push_host_samples(std::span<const ToolSample> samples);
    void push_host_mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays);
    /// A follower: one record of the host's stream as it came: a batch (push_host_samples) or a stroke-end, undo or
    /// redo mark (push_host_mark). Throws tridex::Error as those do, or for another kind of record.
    void push_host_record(const compute::JournalRecord& r);
    /// A follower: the host's model digest (compute::model_digest) after every record queued so far.
    void push_host_check(std::uint64_t digest);
    /// A host: asks the sculpt thread for a snapshot of the session as it stands, for `site` joining late
    /// (SculptThread::use_snapshots). Throws tridex::Error when site is 0 or >= kMaxSites.
    void push_snapshot(std::uint8_t site);
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
