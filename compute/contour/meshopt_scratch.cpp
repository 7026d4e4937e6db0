// compute/contour/meshopt_scratch.cpp - meshoptimizer's scratch memory from a stack per thread.
//
// meshoptimizer allocates its working arrays on every call (meshopt_Allocator) and frees them, in reverse order,
// when the call returns. Through operator new, the large ones are mapped fresh each time and their pages faulted
// in again: about 40 % of a simplification's time on the levels of detail of a tile. Here each thread keeps one
// stack of memory that every call reuses (blocks beyond its capacity still go to operator new). Installed once,
// before main() starts any thread (meshopt_setAllocator sets process-wide function pointers).
#include "compute/contour/meshopt_scratch.hpp"

#include <cstddef>
#include <memory>
#include <new>

#include <meshoptimizer.h>

namespace tridex::compute {
namespace {

class ScratchStack {
public:
    static constexpr std::size_t kCapacity = std::size_t{8} << 20;  // bytes; pages are touched only where used
    static constexpr std::size_t kAlign = 16;

    void* allocate(std::size_t bytes) {
        const std::size_t size = (bytes + kAlign - 1) & ~(kAlign - 1);
        if (!base_) base_.reset(new std::byte[kCapacity]);  // default-initialised: no page is touched yet
        if (size > kCapacity - top_) return ::operator new(bytes);
        void* p = base_.get() + top_;
        top_ += size;
        return p;
    }
    // Blocks are freed in reverse order of allocation (meshopt_Allocator), so freeing one pops the stack to it.
    void deallocate(void* p) {
        auto* b = static_cast<std::byte*>(p);
        if (base_ && b >= base_.get() && b < base_.get() + kCapacity)
            top_ = static_cast<std::size_t>(b - base_.get());
        else
            ::operator delete(p);
    }

private:
    std::unique_ptr<std::byte[]> base_;
    std::size_t top_ = 0;
};

thread_local ScratchStack scratch;

void* allocate(std::size_t bytes) { return scratch.allocate(bytes); }
void deallocate(void* p) { scratch.deallocate(p); }

// Static initialisation: before main(), so before any thread runs meshoptimizer.
const bool installed = [] {
    meshopt_setAllocator(allocate, deallocate);
    return true;
}();

}  // namespace

bool meshopt_scratch_installed() { return installed; }

}  // namespace tridex::compute
