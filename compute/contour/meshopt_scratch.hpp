// compute/contour/meshopt_scratch.hpp - meshoptimizer's scratch memory from a reused stack per thread.
#pragma once

namespace tridex::compute {

/// True once meshoptimizer allocates its scratch arrays from a stack of memory per thread (8 MiB, reused by every
/// call on that thread; larger needs fall back to operator new) instead of operator new: installed by a static
/// initialiser of its translation unit, before main(), which calling this function links in. Every user of
/// meshoptimizer in tridex calls it before its first meshoptimizer call.
bool meshopt_scratch_installed();

}  // namespace tridex::compute
