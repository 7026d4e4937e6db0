// core/spsc_ring.hpp - bounded single-producer single-consumer ring, lock-free and wait-free.
#pragma once

#include <atomic>
#include <cstddef>
#include <new>
#include <vector>

namespace tridex {

/// Fixed-capacity FIFO between exactly one producer thread and one consumer thread.
/// All storage is allocated in the constructor; try_push / try_pop never allocate, lock or wait,
/// so the producer may be the 1 kHz haptic thread. T must be default-constructible and copy-assignable.
template <class T>
class SpscRing {
public:
    /// capacity: the number of elements the ring holds (rounded up to a power of two, >= 2; at most
    /// 2^62, far beyond memory: std::bad_alloc before that).
    explicit SpscRing(std::size_t capacity) {
        std::size_t n = 2;
        while (n < capacity) n <<= 1;
        slots_.resize(n);
        mask_ = n - 1;
    }

    /// Producer side: appends v; returns false (and changes nothing) when the ring is full.
    bool try_push(const T& v) {
        const std::size_t head = head_.load(std::memory_order_relaxed);
        if (head - tail_cache_ > mask_) {
            tail_cache_ = tail_.load(std::memory_order_acquire);
            if (head - tail_cache_ > mask_) return false;
        }
        slots_[head & mask_] = v;
        head_.store(head + 1, std::memory_order_release);
        return true;
    }

    /// Consumer side: removes the oldest element into out; returns false when the ring is empty.
    bool try_pop(T& out) {
        const std::size_t tail = tail_.load(std::memory_order_relaxed);
        if (tail == head_cache_) {
            head_cache_ = head_.load(std::memory_order_acquire);
            if (tail == head_cache_) return false;
        }
        out = slots_[tail & mask_];
        tail_.store(tail + 1, std::memory_order_release);
        return true;
    }

    /// Number of slots.
    std::size_t capacity() const { return mask_ + 1; }
    /// Elements waiting, as seen by the calling thread (any thread; exact only when neither side is active).
    std::size_t size() const { return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire); }

private:
    static constexpr std::size_t kLine = 64;
    std::vector<T> slots_;
    std::size_t mask_ = 0;
    alignas(kLine) std::atomic<std::size_t> head_{0};  // written by the producer
    std::size_t tail_cache_ = 0;                       // producer's view of tail_
    alignas(kLine) std::atomic<std::size_t> tail_{0};  // written by the consumer
    std::size_t head_cache_ = 0;                       // consumer's view of head_
};

}  // namespace tridex
