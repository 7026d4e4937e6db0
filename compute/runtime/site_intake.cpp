// compute/runtime/site_intake.cpp - other sites' samples and requests, queued for the sculpt thread.
#include "compute/runtime/site_intake.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "compute/journal/journal_format.hpp"
#include "core/error.hpp"

namespace tridex::app {

namespace {
// A sample from another machine carries no time of this machine's clock: its arrival stands in (ToolSample::made_s),
// so latency figures here run from it.
double arrival_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void check_site(std::uint8_t site, const char* what) {
    if (site == 0 || site >= kMaxSites)
        throw Error(std::string("site intake: ") + what + " of site " + std::to_string(site) +
                    ": another site is 1.." + std::to_string(kMaxSites - 1) + " (0 is the session's own tool)");
}
}  // namespace

void SiteIntake::push_samples(std::span<const ToolSample> samples) {
    for (const ToolSample& s : samples) check_site(s.site, "a sample");
    const double now = arrival_s();
    std::lock_guard lock(mutex_);
    for (const ToolSample& s : samples) {
        if (queue_.size() >= kMaxEntries) {
            ++dropped_;
            continue;
        }
        SiteEntry& e = queue_.emplace_back();
        e.sample = s;
        if (!std::isfinite(e.sample.made_s)) e.sample.made_s = now;
        e.site = s.site;
    }
}

void SiteIntake::push_host_samples(std::span<const ToolSample> samples) {
    for (const ToolSample& s : samples)
        if (s.site >= kMaxSites)
            throw Error("site intake: the host's sample of site " + std::to_string(s.site) + ": sites are 0.." +
                        std::to_string(kMaxSites - 1));
    const double now = arrival_s();
    std::lock_guard lock(mutex_);
    for (const ToolSample& s : samples) {
        SiteEntry& e = queue_.emplace_back();
        e.sample = s;
        if (!std::isfinite(e.sample.made_s)) e.sample.made_s = now;
        e.site = s.site;
    }
}

void SiteIntake::push_host_mark(std::uint32_t type, std::uint64_t serial, std::uint64_t rays) {
    if (type != compute::kJournalStrokeEnd && type != compute::kJournalUndo && type != compute::kJournalRedo)
        throw Error("site intake: the host's mark of type " + std::to_string(type) + " is none of stroke end, undo, redo");
    std::lock_guard lock(mutex_);
    SiteEntry& e = queue_.emplace_back();
    e.kind = SiteEntry::kMark;
    e.mark = type;
    e.serial = serial;
    e.rays = rays;
}

void SiteIntake::push_host_record(const compute::JournalRecord& r) {
    switch (r.kind) {
        case compute::JournalKind::kBatch: return push_host_samples(r.samples);
        case compute::JournalKind::kStrokeEnd: return push_host_mark(compute::kJournalStrokeEnd, r.serial, r.rays);
        case compute::JournalKind::kUndo: return push_host_mark(compute::kJournalUndo, r.serial, r.rays);
        case compute::JournalKind::kRedo: return push_host_mark(compute::kJournalRedo, r.serial, r.rays);
        default: throw Error("site intake: the host's stream holds a record of kind " + std::to_string(static_cast<int>(r.kind)));
    }
}

void SiteIntake::push_host_check(std::uint64_t digest) {
    std::lock_guard lock(mutex_);
    SiteEntry& e = queue_.emplace_back();
    e.kind = SiteEntry::kCheck;
    e.serial = digest;
}

void SiteIntake::push_snapshot(std::uint8_t site) {
    check_site(site, "a snapshot");
    std::lock_guard lock(mutex_);
    SiteEntry& e = queue_.emplace_back();
    e.kind = SiteEntry::kSnapshot;
    e.site = site;
}

void SiteIntake::push_request(std::uint8_t site, SculptRequest r) {
    check_site(site, "a request");
    if (r == SculptRequest::kSave) throw Error("site intake: site " + std::to_string(site) + " asked to save");
    std::lock_guard lock(mutex_);
    if (queue_.size() >= kMaxEntries) {
        ++dropped_;
        return;
    }
    SiteEntry& e = queue_.emplace_back();
    e.kind = SiteEntry::kRequest;
    e.request = r;
    e.site = site;
}

std::size_t SiteIntake::drain(std::vector<SiteEntry>& out) {
    std::lock_guard lock(mutex_);
    const std::size_t n = queue_.size();
    out.insert(out.end(), queue_.begin(), queue_.end());
    queue_.clear();
    return n;
}

std::size_t SiteIntake::pending() const {
    std::lock_guard lock(mutex_);
    return queue_.size();
}

std::uint64_t SiteIntake::dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
}

}  // namespace tridex::app
