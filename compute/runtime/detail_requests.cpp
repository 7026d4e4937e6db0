// compute/runtime/detail_requests.cpp - requests for full-resolution tiles from the frames.
#include "compute/runtime/detail_requests.hpp"

#include <algorithm>

namespace tridex::compute {

void DetailRequests::offer(std::span<const std::uint64_t> group_ids) {
    if (group_ids.empty()) return;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const std::uint64_t id : group_ids) {
        if (ids_.size() >= kMaxIds) {  // frames repeat their requests: drop the repeats before refusing any
            std::sort(ids_.begin(), ids_.end());
            ids_.erase(std::unique(ids_.begin(), ids_.end()), ids_.end());
            if (ids_.size() >= kMaxIds) break;
        }
        ids_.push_back(id);
    }
}

std::vector<std::uint64_t> DetailRequests::take() {
    std::vector<std::uint64_t> out;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        out.swap(ids_);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace tridex::compute
