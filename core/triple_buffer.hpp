// core/triple_buffer.hpp - lock-free "latest snapshot" hand-off from one writer to one reader.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>

namespace tridex {

/// Three preallocated copies of T. The writer fills back() and publish()es it; the reader
/// gets the newest complete copy with latest(). Neither side ever locks, waits or allocates,
/// and the reader never sees a half-written T (the writer never touches the slot the reader holds).
/// Exactly one writer thread and one reader thread.
template <class T>
class TripleBuffer {
public:
    /// Allocates the three copies (value-initialised) on the heap.
    TripleBuffer() : slots_(std::make_unique<std::array<T, 3>>()) {}

    /// Writer side: the slot to fill before publish(). Its contents are stale (two publishes old).
    T& back() { return (*slots_)[write_]; }

    /// Writer side: makes back() the newest snapshot and hands the writer a free slot.
    void publish() {
        const std::uint8_t prev = middle_.exchange(static_cast<std::uint8_t>(write_ | kFresh),
                                                   std::memory_order_acq_rel);
        write_ = prev & kIndex;
    }

    /// Writer side: true while the newest published snapshot has not been taken by latest() (the next publish()
    /// would replace it unseen). The reader may take it at any moment, so true may be out of date at once; false
    /// stays false until the next publish().
    bool unread() const { return (middle_.load(std::memory_order_acquire) & kFresh) != 0; }

    /// Reader side: the newest published snapshot (or the value-initialised T before any publish).
    /// The reference stays valid and unchanged until the next latest() call on this thread.
    const T& latest() {
        if (middle_.load(std::memory_order_acquire) & kFresh) {
            const std::uint8_t prev = middle_.exchange(read_, std::memory_order_acq_rel);
            read_ = prev & kIndex;
        }
        return (*slots_)[read_];
    }

private:
    static constexpr std::uint8_t kFresh = 4;
    static constexpr std::uint8_t kIndex = 3;
    std::unique_ptr<std::array<T, 3>> slots_;
    std::uint8_t write_ = 0;             // writer-owned
    std::uint8_t read_ = 1;              // reader-owned
    std::atomic<std::uint8_t> middle_{2};  // shared; kFresh set when it holds an unread snapshot
};

}  // namespace tridex
