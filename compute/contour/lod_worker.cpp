// compute/contour/lod_worker.cpp - the level-of-detail worker threads.
#include "compute/contour/lod_worker.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#if defined(__linux__)
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

#include "compute/contour/tile_group_lod.hpp"
#include "core/error.hpp"
#include "core/thread_name.hpp"

namespace tridex::compute {
namespace {

// Lowers the calling thread's priority to `nice` (Linux: the nice value is per thread). Lowering never needs a
// privilege; a failure leaves the thread as it was.
void lower_priority(int nice) {
#if defined(__linux__)
    if (nice > 0) (void)setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), nice);
#else
    (void)nice;
#endif
}

std::vector<TileLodLevel> build(const LodJob& job, const TileLodOptions& o) {
    if (!job.group)
        return job.levels ? build_lod_levels(job.mesh, job.materials, job.normals, 0.0, o)
                          : std::vector<TileLodLevel>{};
    std::vector<LodPart> parts;
    parts.reserve(job.parts.size());
    for (const LodJobPart& p : job.parts) parts.push_back(LodPart{&p.mesh, p.materials, p.normals, p.error_m});
    return build_group_lod(parts, o);
}

}  // namespace

LodWorker::LodWorker(LodWorkerOptions options) : options_(std::move(options)) {
    if (!std::isfinite(options_.lod.cell_m) || !(options_.lod.cell_m > 0.0))
        throw Error("LodWorker: cell_m must be finite and > 0, got " + std::to_string(options_.lod.cell_m));
    if (options_.threads < 1) throw Error("LodWorker: threads must be >= 1, got " + std::to_string(options_.threads));
    if (options_.nice < 0 || options_.nice > 19)
        throw Error("LodWorker: nice must lie in 0..19, got " + std::to_string(options_.nice));
    if (options_.startup_nice < 0 || options_.startup_nice > options_.nice)
        throw Error("LodWorker: startup_nice must lie in 0..nice (" + std::to_string(options_.nice) + "), got " +
                    std::to_string(options_.startup_nice));
    if (!(options_.group_settle_s >= 0.0 && options_.group_settle_s <= 10.0))
        throw Error("LodWorker: group_settle_s must lie in 0..10 s, got " + std::to_string(options_.group_settle_s));
    if (!(options_.tile_settle_s >= 0.0 && options_.tile_settle_s <= 10.0))
        throw Error("LodWorker: tile_settle_s must lie in 0..10 s, got " + std::to_string(options_.tile_settle_s));
    for (int i = 0; i < options_.threads; ++i) threads_.emplace_back([this] { run(); });
}

LodWorker::~LodWorker() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
        queue_.clear();
        waiting_tiles_.clear();
        waiting_groups_.clear();
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
}

void LodWorker::submit(LodJob job, bool urgent) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        auto& index = waiting(job.group);
        const auto same = index.find(job.id);
        if (same != index.end()) queue_.erase(same->second);
        const std::uint64_t id = job.id;
        const auto at = urgent ? queue_.insert(queue_.begin(), std::move(job)) : queue_.insert(queue_.end(), std::move(job));
        index[id] = at;
    }
    wake_.notify_one();
}

bool LodWorker::cancel(bool group, std::uint64_t id) {
    const std::lock_guard<std::mutex> lock(mutex_);
    auto& index = waiting(group);
    const auto same = index.find(id);
    if (same == index.end()) return false;
    queue_.erase(same->second);
    index.erase(same);
    return true;
}

std::size_t LodWorker::take(std::vector<LodResult>& out) {
    std::exception_ptr failure;
    std::size_t n = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        n = done_.size();
        for (LodResult& r : done_) out.push_back(std::move(r));
        done_.clear();
        failure = std::exchange(failure_, nullptr);
    }
    if (failure) std::rethrow_exception(failure);
    return n;
}

std::size_t LodWorker::outstanding() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return queue_.size() + running_;
}

void LodWorker::run() {
    name_this_thread("tridex-lod");
    lower_priority(options_.startup_nice);
    bool lowered = false;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
        if (stop_) return;
        LodJob job = std::move(queue_.front());
        queue_.pop_front();
        waiting(job.group).erase(job.id);
        ++running_;
        lock.unlock();
        if (!lowered && startup_over_.load(std::memory_order_acquire)) {
            lower_priority(options_.nice);
            lowered = true;
        }
        LodResult r{job.group, job.id, job.token, {}, {}, 0.0};
        std::exception_ptr failed;
        const auto t0 = std::chrono::steady_clock::now();
        try {
            if (options_.before_job) options_.before_job(job);
            if (!job.group) order_for_vertex_cache(job.mesh);  // off the sculpt thread, which publishes it unordered
            r.levels = build(job, options_.lod);
            if (!job.group) r.mesh = std::move(job.mesh);
        } catch (...) {
            failed = std::current_exception();
        }
        r.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        lock.lock();
        --running_;
        if (failed) {
            if (!failure_) failure_ = failed;
        } else {
            done_.push_back(std::move(r));
        }
    }
}

}  // namespace tridex::compute
