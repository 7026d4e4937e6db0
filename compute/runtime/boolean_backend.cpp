// compute/runtime/boolean_backend.cpp - the CPU and GPU sculpting backends.
#include "compute/runtime/boolean_backend.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>

#include "compute/gpu/gpu_clay.hpp"
#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/tools/sweep_parallel.hpp"
#include "compute/tools/clay_sweep.hpp"
#include "core/error.hpp"
#include "gpu/context.hpp"

namespace tridex::app {
namespace {

class CpuBackend final : public BooleanBackend {
public:
    explicit CpuBackend(compute::TriDexel& model) : model_(model) {}
    // Boolean sweeps on every core through the task pool (bit for bit apply_sweep one by one), clay sweeps through
    // apply_clay_batch; validates the whole batch first, so a bad sweep changes nothing.
    compute::BooleanStats apply(std::span<const compute::Sweep> batch) override {
        compute::to_grid_batch(model_.lattice, batch);  // validate all first: a bad sweep changes nothing
        compute::BooleanStats total;
        const auto add = [&](const compute::BooleanStats& b) {
            total.rays_visited += b.rays_visited;
            total.rays_changed += b.rays_changed;
        };
        // Runs of Boolean sweeps go to the task pool together, runs of clay sweeps to apply_clay_batch, in batch order.
        std::size_t k = 0;
        while (k < batch.size()) {
            const bool clay = compute::is_clay_op(batch[k].op);
            std::size_t e = k;
            while (e < batch.size() && compute::is_clay_op(batch[e].op) == clay) ++e;
            add(clay ? compute::apply_clay_batch(model_, batch.subspan(k, e - k), nullptr, compute::clay_cpu_kernel(),
                                                 clay_group_sweeps_)
                     : compute::apply_sweeps_parallel(model_, batch.subspan(k, e - k), 0));
            k = e;
        }
        return total;
    }
    void write_rays(std::span<const compute::RayImage> rays, const Aabb& box_m) override {
        for (const compute::RayImage& r : rays) {
            if (r.axis > 2 || r.index >= model_.sets[r.axis].rays.size())
                throw Error("tri-dexel: ray image outside the model (axis " + std::to_string(r.axis) + ", ray " +
                            std::to_string(r.index) + ")");
            model_.sets[r.axis].rays[r.index] = r.intervals;
        }
        if (!rays.empty()) model_.mark_dirty(box_m);
    }
    std::string path() const override { return "cpu"; }
    std::string device() const override { return ""; }
    std::uint64_t spilled_intervals() const override { return 0; }
    std::array<std::size_t, 3> model_bytes() const override { return cpu_model_bytes(model_); }
    std::uint32_t validation_messages() const override { return 0; }

private:
    compute::TriDexel& model_;
};

class GpuBackend final : public BooleanBackend {
public:
    // Owning its Context.
    GpuBackend(gpu::Context context, compute::TriDexel& model, bool gpu_clay)
        : own_(std::move(context)), context_(*own_), sculptor_(std::make_unique<compute::GpuSculptor>(context_, model)),
          mirror_(&model) {
        place_clay(gpu_clay);
    }
    // On a shared Context.
    GpuBackend(const gpu::Context* shared, compute::TriDexel& model, bool gpu_clay)
        : context_(*shared), sculptor_(std::make_unique<compute::GpuSculptor>(context_, model)), mirror_(&model) {
        place_clay(gpu_clay);
    }
    ~GpuBackend() override {
        clay_.reset();  // GPU objects before the context
        sculptor_.reset();
        if (own_ && context_.validation_messages() > 0)
            std::fprintf(stderr, "tridex: %u Vulkan validation messages on the sculpting device\n", context_.validation_messages());
    }
    /// Booleans run on the GPU kernel (GpuSculptor); a clay sweep (push, smooth, pull, grab) runs on the GPU clay
    /// kernel (GpuClay: field and re-sampling in Vulkan compute, contacts and the beta solve on the host), which writes
    /// the changed rays to the mirror (marking its dirty tiles) and to the slabs, or, where the clay is placed on the
    /// CPU, the CPU reference on the mirror with its changed rays written to the slabs; sweeps apply in batch order,
    /// runs of clay sweeps through apply_clay_batch (the same grouping as the CPU backend, so both give one model).
    compute::BooleanStats apply(std::span<const compute::Sweep> batch) override {
        if (std::none_of(batch.begin(), batch.end(), [](const compute::Sweep& s) { return compute::is_clay_op(s.op); }))
            return sculptor_->apply(batch);
        compute::to_grid_batch(sculptor_->mirror().lattice, batch);  // validate all first: a bad sweep changes nothing
        compute::BooleanStats total;
        std::size_t i = 0;
        while (i < batch.size()) {
            std::size_t j = i;
            while (j < batch.size() && !compute::is_clay_op(batch[j].op)) ++j;
            if (j > i) {
                const compute::BooleanStats b = sculptor_->apply(batch.subspan(i, j - i));
                total.rays_visited += b.rays_visited;
                total.rays_changed += b.rays_changed;
            }
            if (j < batch.size()) {
                std::size_t e = j;
                while (e < batch.size() && compute::is_clay_op(batch[e].op)) ++e;
                const compute::BooleanStats c =
                    clay_ ? compute::apply_clay_batch(sculptor_->mirror(), batch.subspan(j, e - j), nullptr, *clay_,
                                                      clay_group_sweeps_)
                          : clay_on_mirror(batch.subspan(j, e - j));
                total.rays_visited += c.rays_visited;
                total.rays_changed += c.rays_changed;
                j = e;
            }
            i = j;
        }
        return total;
    }
    void write_rays(std::span<const compute::RayImage> rays, const Aabb& box_m) override { sculptor_->write_rays(rays, box_m); }
    void relattice() override {
        compute::TriDexel& m = *mirror_;
        const bool gpu_clay = clay_ != nullptr;
        clay_.reset();  // the old slabs go first: the device holds one lattice at a time
        sculptor_.reset();
        sculptor_ = std::make_unique<compute::GpuSculptor>(context_, m);
        if (gpu_clay) clay_ = std::make_unique<compute::GpuClay>(context_, *sculptor_);
    }
    std::string path() const override { return "gpu"; }
    std::string device() const override { return context_.device_name(); }
    std::uint64_t spilled_intervals() const override { return sculptor_->slabs().spilled_intervals(); }
    std::array<std::size_t, 3> model_bytes() const override {
        const auto b = sculptor_->slabs().bytes();
        return {b[0].total(), b[1].total(), b[2].total()};
    }
    std::uint32_t validation_messages() const override { return own_ ? context_.validation_messages() : 0u; }
    const compute::GpuDexelSlabs* gpu_slabs() const override { return &sculptor_->slabs(); }
    const gpu::Context* gpu_context() const override { return &context_; }
    const compute::GpuClayStats* gpu_clay_stats() const override { return clay_ ? &clay_->stats() : nullptr; }
    std::string clay_path() const override { return clay_ ? "gpu" : "cpu"; }
    std::string clay_reason() const override { return clay_reason_; }

private:
    // The GPU clay kernel on a real GPU or when asked; the CPU reference on a CPU implementation of Vulkan.
    void place_clay(bool gpu_clay) {
        if (gpu_clay || context_.properties().deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU) {
            clay_ = std::make_unique<compute::GpuClay>(context_, *sculptor_);
            return;
        }
        clay_reason_ = "the Vulkan device (" + context_.device_name() +
                       ") is a CPU implementation, where the clay tools' CPU reference is faster; --gpu-clay forces "
                       "the GPU clay kernel";
    }
    // The CPU reference on the mirror (apply_clay_batch); its changed rays are written to the slabs.
    compute::BooleanStats clay_on_mirror(std::span<const compute::Sweep> run) {
        std::vector<compute::RayImage> before;
        compute::TriDexel& m = sculptor_->mirror();
        const compute::BooleanStats c =
            compute::apply_clay_batch(m, run, &before, compute::clay_cpu_kernel(), clay_group_sweeps_);
        for (compute::RayImage& r : before) r.intervals = m.sets[r.axis].rays[r.index];  // the new images
        if (!before.empty()) {
            Aabb box;
            for (const compute::Sweep& s : run) {
                const Aabb b = compute::clay_bounds(m.lattice, s);
                if (!b.empty()) box.add(b.lo), box.add(b.hi);
            }
            sculptor_->write_rays(before, box);
        }
        return c;
    }

    std::string clay_reason_;
    std::optional<gpu::Context> own_;  // empty when sculpting on a shared Context
    const gpu::Context& context_;
    std::unique_ptr<compute::GpuSculptor> sculptor_;
    std::unique_ptr<compute::GpuClay> clay_;
    compute::TriDexel* mirror_ = nullptr;  // the CPU model (the sculptor's mirror), for relattice()
};

}  // namespace

std::array<std::size_t, 3> cpu_model_bytes(const compute::TriDexel& model) {
    std::array<std::size_t, 3> bytes{};
    for (int a = 0; a < 3; ++a) {
        std::size_t b = model.sets[a].rays.size() * sizeof(std::vector<compute::Interval>);
        for (const auto& ray : model.sets[a].rays) b += ray.capacity() * sizeof(compute::Interval);
        bytes[a] = b;
    }
    return bytes;
}

std::unique_ptr<BooleanBackend> make_cpu_backend(compute::TriDexel& model) { return std::make_unique<CpuBackend>(model); }

BackendChoice make_boolean_backend(compute::TriDexel& model, const BackendRequest& request, bool validate) {
    BackendChoice choice;
    SculptDevice device;
    std::optional<gpu::Context> context;
    if (request.mode != BackendMode::kCpu) {
        gpu::ContextOptions opt;
        opt.validation = validate;
        try {
            context.emplace(gpu::Context::create(opt));
            device.type = context->properties().deviceType;
            device.name = context->device_name();
        } catch (const Error& e) {
            device.error = e.what();
        }
    }
    const BackendDecision d = decide_backend(request, device);
    choice.reason = d.reason;
    if (d.gpu)
        choice.backend = std::make_unique<GpuBackend>(std::move(*context), model, request.gpu_clay);
    else
        choice.backend = make_cpu_backend(model);
    return choice;
}

BackendChoice make_boolean_backend_on(compute::TriDexel& model, const BackendRequest& request, gpu::Context& shared) {
    BackendChoice choice;
    const SculptDevice device{shared.properties().deviceType, shared.device_name(), ""};
    const BackendDecision d = decide_backend(request, device);
    choice.reason = d.reason;
    if (d.gpu)
        choice.backend = std::make_unique<GpuBackend>(static_cast<const gpu::Context*>(&shared), model, request.gpu_clay);
    else
        choice.backend = make_cpu_backend(model);
    return choice;
}

}  // namespace tridex::app
