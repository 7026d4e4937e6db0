// compute/runtime/boolean_backend.hpp - where the sculpt thread's swept Booleans run: the GPU (Vulkan compute) or the
// CPU (all cores on the task pool).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "compute/gpu/gpu_clay.hpp"
#include "compute/gpu/gpu_dexel_slabs.hpp"
#include "compute/model/tridexel.hpp"
#include "compute/runtime/backend_choice.hpp"
#include "compute/tools/boolean.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "compute/tools/sweep.hpp"
#include "gpu/context.hpp"

namespace tridex::app {

/// Applies batches of sweeps to a tri-dexel model (the model the sculpt thread contours and publishes).
/// Both implementations give the same model (tests/compute/test_gpu_sculptor.cpp). Not thread-safe:
/// the sculpt thread is its one user.
class BooleanBackend {
public:
    virtual ~BooleanBackend() = default;
    /// Applies `batch` in order to the model and marks its dirty tiles; clay sweeps (ToolOp kPush, kSmooth, kPull,
    /// kGrab) run apply_clay (compute/tools/clay_sweep.hpp) on the CPU reference or, on the GPU path, on the GPU clay
    /// kernel (compute/gpu/gpu_clay.hpp), with the same result bit for bit. Throws tridex::Error on a bad sweep
    /// (nothing changed) or a device failure.
    virtual compute::BooleanStats apply(std::span<const compute::Sweep> batch) = 0;
    /// Replaces whole rays of the model (undo and redo) on this path's storage and in the CPU model, and marks
    /// the model's tiles around `box_m` (world m) dirty. Throws tridex::Error on an image outside the model or a
    /// device failure.
    virtual void write_rays(std::span<const compute::RayImage> rays, const Aabb& box_m) = 0;
    /// Makes this path's storage again for the model's lattice after the CPU model was replaced whole (a coarseness
    /// change, its undo or redo: app::SculptHistory::resample): the GPU path builds its slabs (and its clay kernel)
    /// again from the CPU model; the CPU path has nothing to do. Throws tridex::Error when the model does not fit the
    /// device; the backend then holds no storage until a relattice() that succeeds.
    virtual void relattice() {}
    /// "gpu" or "cpu" (report.json `sculpt_path`).
    virtual std::string path() const = 0;
    /// The Vulkan device name for "gpu"; "" for "cpu".
    virtual std::string device() const = 0;
    /// Intervals held in the GPU spill pool (report.json `spilled_intervals`); 0 for "cpu".
    virtual std::uint64_t spilled_intervals() const = 0;
    /// Bytes of the model per ray set (X, Y, Z) on the path's storage: GPU slabs, or the CPU vectors.
    virtual std::array<std::size_t, 3> model_bytes() const = 0;
    /// Vulkan validation messages on the sculpting device so far (0 on the CPU path or with validation off,
    /// and 0 when the backend sculpts on a Context it shares: its owner counts them).
    virtual std::uint32_t validation_messages() const = 0;
    /// The GPU-resident model (GpuSculptor::slabs) on the "gpu" path; nullptr on the CPU path.
    virtual const compute::GpuDexelSlabs* gpu_slabs() const { return nullptr; }
    /// The Context the GPU path sculpts on (its own or the shared one); nullptr on the CPU path.
    virtual const gpu::Context* gpu_context() const { return nullptr; }
    /// Counters of the GPU clay kernel (fields built, rays re-sampled on the GPU or handed back to the host) on the
    /// "gpu" path; nullptr on the CPU path.
    virtual const compute::GpuClayStats* gpu_clay_stats() const { return nullptr; }
    /// Where clay sweeps run: "gpu" (the GPU clay kernel) or "cpu" (the CPU reference; on the GPU path on the
    /// mirror, its changed rays written to the slabs). Both give the same model bit for bit.
    virtual std::string clay_path() const { return "cpu"; }
    /// Why clay sweeps run on the CPU on the GPU path ("" otherwise), e.g. a CPU implementation of Vulkan.
    virtual std::string clay_reason() const { return ""; }
    /// Sets the most sweeps one push or smooth group holds (compute::apply_clay_batch's group_sweeps; default
    /// compute::kClayGroupSweeps). The grouping decides the model, so a session sets the size its spec records
    /// (SessionSpec::clay_group_sweeps) and a replay the one its recording says. Throws tridex::Error as
    /// compute::check_clay_group_sweeps.
    void set_clay_group_sweeps(std::size_t n) {
        compute::check_clay_group_sweeps(n);
        clay_group_sweeps_ = n;
    }
    /// The most sweeps one push or smooth group holds (set_clay_group_sweeps).
    std::size_t clay_group_sweeps() const { return clay_group_sweeps_; }

protected:
    std::size_t clay_group_sweeps_ = compute::kClayGroupSweeps;  ///< apply_clay_batch's group_sweeps
};

/// What make_boolean_backend chose, and why.
struct BackendChoice {
    std::unique_ptr<BooleanBackend> backend;
    /// Why this backend (decide_backend's reason: "--cpu given", "auto: the Vulkan device is a CPU implementation
    /// (llvmpipe ...)", ...); never empty once chosen.
    std::string reason;
    /// The reason on the CPU path, "" on the GPU path (report.json `sculpt_path_reason`).
    std::string cpu_reason() const { return backend && backend->path() == "cpu" ? reason : std::string(); }
};

/// The CPU backend on `model`: each batch on every core through the task pool (compute::apply_sweeps_parallel,
/// bit for bit the CPU reference apply_sweep per sweep). `model` must outlive it.
std::unique_ptr<BooleanBackend> make_cpu_backend(compute::TriDexel& model);

/// The backend decide_backend(request, device) chooses, where `device` is the one a Context of its own would
/// sculpt on (created unless request.mode is kCpu; validation when `validate` or TRIDEX_VALIDATION=1; dropped again
/// when the CPU pool is chosen). Throws tridex::Error for flags that disagree, --gpu without a usable device, or a
/// model that does not fit the device (the numbers in the message; never silently moved to the CPU).
/// On the GPU path clay sweeps run on the GPU clay kernel on a real GPU, and on the CPU reference (on the mirror,
/// the changed rays written to the slabs) on a CPU implementation of Vulkan (lavapipe), where the kernel's
/// submissions cost more than the reference; request.gpu_clay runs them on the kernel there too.
BackendChoice make_boolean_backend(compute::TriDexel& model, const BackendRequest& request, bool validate);

/// As above, but deciding on `shared`'s device, and the GPU path sculpts on `shared` (e.g. the renderer's Context,
/// so that the renderer can draw buffers the sculpt thread fills; submissions from both threads are serialised by
/// the Context) instead of a Context of its own; `shared` must outlive the backend. Throws as above.
BackendChoice make_boolean_backend_on(compute::TriDexel& model, const BackendRequest& request, gpu::Context& shared);

/// Bytes the CPU reference model takes per ray set (vector headers plus interval storage).
std::array<std::size_t, 3> cpu_model_bytes(const compute::TriDexel& model);

}  // namespace tridex::app
