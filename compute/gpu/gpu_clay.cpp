// compute/gpu/gpu_clay.cpp - the clay field and re-sampling dispatches, and the host's share (chords, beta, writing).
#include "compute/gpu/gpu_clay.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <string>

#include "compute/tools/clay_push.hpp"
#include "compute/tools/clay_smooth.hpp"
#include "core/error.hpp"
#include "gpu/check.hpp"
#include "gpu/descriptor_sets.hpp"
#include "gpu/compute_pipeline.hpp"
#include "shaders/spirv.hpp"

namespace tridex::compute {

/// The operation as shaders/clay_field.comp reads it (binding 18, a std140 uniform buffer; the chords and the stamps go
/// in binding 21).
struct GpuClay::Header {
    std::int32_t box_lo[4] = {0, 0, 0, 0};
    std::int32_t box_hi[4] = {0, 0, 0, 0};
    std::int32_t box_n[4] = {0, 0, 0, 0};
    std::int32_t move_lo[4] = {0, 0, 0, 0};
    std::int32_t move_hi[4] = {0, 0, 0, 0};
    std::int32_t ray_nu[4] = {0, 0, 0, 0};
    std::uint32_t chord_at[4] = {0, 0, 0, 0};
    std::uint32_t counts[4] = {0, 0, 0, 0};
    float consts[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    float stamp_par[4] = {0.0f, 0.0f, 0.0f, 0.0f};
};

namespace {

constexpr std::uint32_t kBindings = 22;   // 21 storage buffers and the plan's uniform buffer
constexpr std::uint32_t kPlanBinding = 18;
constexpr std::size_t kPlanBytes = 160;
constexpr std::uint32_t kNodeGroup = 64;  // invocations per workgroup of the node kernels (MODE 0-2, 4)
constexpr std::uint32_t kRayGroup = 8;    // ... of the ray kernel (MODE 3): one SIMD row of llvmpipe
constexpr std::uint32_t kMaxGroups = 65535;
constexpr std::uint32_t kJobWords = 8;
constexpr std::uint32_t kOverflow = 0xffffffffu;

struct Push {
    std::uint32_t first, count;
    float beta;
    std::uint32_t act;  // MODE 2: the smooth act of this dispatch
};

gpu::Buffer host_storage(const gpu::Context& c, std::size_t bytes) {
    return gpu::Buffer::create(c, std::max<std::size_t>(bytes, 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryDomain::kHost);
}

// Grows `buf` to at least `bytes` (doubling); true when it was replaced.
bool ensure(const gpu::Context& c, gpu::Buffer& buf, std::size_t bytes) {
    if (buf.handle() != VK_NULL_HANDLE && buf.size() >= bytes) return false;
    buf = host_storage(c, std::max<std::size_t>(bytes, buf.handle() != VK_NULL_HANDLE ? 2 * buf.size() : 0));
    return true;
}

void barrier(VkCommandBuffer cmd, VkAccessFlags dst_access, VkPipelineStageFlags dst_stage) {
    VkMemoryBarrier b{};
    b.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    b.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    b.dstAccessMask = dst_access;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, dst_stage, 0, 1, &b, 0, nullptr, 0, nullptr);
}

}  // namespace

GpuClay::GpuClay(const gpu::Context& context, GpuSculptor& sculptor, const GpuClayOptions& options)
    : context_(context), sculptor_(sculptor), options_(options) {
    static_assert(sizeof(Header) == kPlanBytes, "Header must match shaders/clay_field.comp's Plan");
    if (options.max_kernel_intervals < 1 || options.max_kernel_intervals > GpuDexelSlabs::kMaxRayIntervals)
        throw Error("GPU clay: max_kernel_intervals must be in 1.." + std::to_string(GpuDexelSlabs::kMaxRayIntervals) +
                    ", got " + std::to_string(options.max_kernel_intervals));
    const VkPhysicalDeviceLimits& lim = context.properties().limits;
    if (lim.maxPerStageDescriptorStorageBuffers < kBindings - 1 || lim.maxDescriptorSetStorageBuffers < kBindings - 1 ||
        lim.maxUniformBufferRange < kPlanBytes)
        throw Error("GPU clay: the device binds " + std::to_string(lim.maxPerStageDescriptorStorageBuffers) +
                    " storage buffers per stage and uniform buffers of " + std::to_string(lim.maxUniformBufferRange) +
                    " bytes, the clay kernel needs " + std::to_string(kBindings - 1) + " and " + std::to_string(kPlanBytes) +
                    "; use --cpu");
    gpu::ComputeLayout cl = gpu::create_compute_layout(context, kBindings, sizeof(Push), 1u << kPlanBinding);
    const VkDescriptorSetLayout layout = cl.set_layout.get();
    set_layout_ = std::move(cl.set_layout);
    pipeline_layout_ = std::move(cl.pipeline_layout);
    module_ = gpu::create_shader_module(context, shaders::spirv("clay_field_comp"));
    descriptor_pool_ = gpu::allocate_descriptor_sets(
        context.device(), {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kBindings - 1}, {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1}},
        layout, 1, &set_);
    for (gpu::Buffer* b : {&phi_, &s0_, &s1_, &chords_, &jobs_, &out_}) *b = host_storage(context_, 4096);
    plan_ = gpu::Buffer::create(context_, kPlanBytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, gpu::MemoryDomain::kHost);
    // Every pipeline now (tens of ms each on lavapipe), and one empty dispatch of each (lavapipe finishes preparing a
    // kernel on its first dispatch; without it a session's first clay operations stall), so that no clay operation
    // waits for either.
    VkPipeline all[7];
    for (std::uint32_t mode = 0; mode < 3; ++mode) all[mode] = pipeline(mode);
    for (std::uint32_t set = 0; set < 3; ++set) all[3 + set] = pipeline(3u, set);
    all[6] = pipeline(4u);
    bind();
    context_.submit_and_wait([&](VkCommandBuffer cmd) {
        const Push none{0, 0, 0.0f, 0};  // count 0: every invocation returns at once
        for (const VkPipeline p : all) {
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_.get(), 0, 1, &set_, 0, nullptr);
            vkCmdPushConstants(cmd, pipeline_layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Push), &none);
            vkCmdDispatch(cmd, 1, 1, 1);
        }
    });
}

GpuClay::~GpuClay() = default;

VkPipeline GpuClay::pipeline(std::uint32_t mode, std::uint32_t set) {
    gpu::UniquePipeline& p = pipelines_[mode == 4u ? 6u : mode + set];
    if (p.get() != VK_NULL_HANDLE) return p.get();
    const std::uint32_t values[3] = {mode, mode == 3 ? kRayGroup : kNodeGroup, set};
    const VkSpecializationMapEntry entries[3] = {{0, 0, 4}, {1, 4, 4}, {2, 8, 4}};
    VkSpecializationInfo spec{};
    spec.mapEntryCount = 3;
    spec.pMapEntries = entries;
    spec.dataSize = sizeof(values);
    spec.pData = values;
    p = gpu::create_compute_pipeline(context_, module_.get(), pipeline_layout_.get(), &spec);
    return p.get();
}

void GpuClay::check_model(const TriDexel& model) const {
    if (&model != &sculptor_.mirror())
        throw Error("GPU clay: the model must be the GPU sculptor's mirror (the slabs hold that one)");
}

bool GpuClay::fits(const ClayField& field) const {
    // s0 holds two floats per node (a smooth's acts step between its halves).
    const std::size_t limit = context_.properties().limits.maxStorageBufferRange / (2 * sizeof(float));
    const std::size_t most = options_.max_field_nodes > 0 ? std::min(options_.max_field_nodes, limit) : limit;
    return field.box.count() <= most;
}

void GpuClay::bind() {
    const GpuDexelSlabs& slabs = sculptor_.slabs();
    const gpu::Buffer* bufs[kBindings];
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 5; ++b) bufs[5 * a + b] = &slabs.buffer(a, b);
    bufs[15] = &phi_;
    bufs[16] = &s0_;
    bufs[17] = &s1_;
    bufs[18] = &plan_;
    bufs[19] = &jobs_;
    bufs[20] = &out_;
    bufs[21] = &chords_;
    VkDescriptorBufferInfo info[kBindings];
    VkWriteDescriptorSet w[kBindings]{};
    for (std::uint32_t i = 0; i < kBindings; ++i) {
        info[i] = VkDescriptorBufferInfo{bufs[i]->handle(), 0, VK_WHOLE_SIZE};
        w[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        w[i].dstSet = set_;
        w[i].dstBinding = i;
        w[i].descriptorCount = 1;
        w[i].descriptorType = i == kPlanBinding ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w[i].pBufferInfo = &info[i];
    }
    vkUpdateDescriptorSets(context_.device(), kBindings, w, 0, nullptr);
}

void GpuClay::build_field(ClayField& f, std::uint32_t mode, Header& h, std::span<const float> stamps) {
    const TriDexel& model = sculptor_.mirror();
    const ClayBox& b = f.box;
    const std::size_t count = b.count();
    clay_build_chords(f);
    words_.clear();
    for (int a = 0; a < 3; ++a) {
        h.chord_at[a] = static_cast<std::uint32_t>(words_.size());
        for (const std::array<int, 2>& run : f.chords[a]) {
            words_.push_back(static_cast<std::uint32_t>(run[0]));
            words_.push_back(static_cast<std::uint32_t>(run[1]));
        }
    }
    for (int a = 0; a < 3; ++a) {
        h.box_lo[a] = b.lo[a];
        h.box_hi[a] = b.hi[a];
        h.box_n[a] = b.n(a);
        clay_movable_range(b, model.lattice, a, h.move_lo[a], h.move_hi[a]);
        h.ray_nu[a] = model.sets[a].nu;
    }
    h.counts[0] = static_cast<std::uint32_t>(count);
    h.counts[2] = options_.max_kernel_intervals;
    h.consts[0] = f.search;
    h.consts[1] = 1e-6f;  // clay_build_phi's floor of |phi|
    h.consts[2] = kClaySmoothRate;
    h.consts[3] = kClayMaxBeta;
    ensure(context_, phi_, count * 4);
    ensure(context_, s0_, count * 8);  // two halves: a smooth's acts step from one into the other
    ensure(context_, s1_, count * 4);
    h.chord_at[3] = static_cast<std::uint32_t>(words_.size());
    for (const float v : stamps) {
        std::uint32_t w;
        std::memcpy(&w, &v, 4);
        words_.push_back(w);
    }
    ensure(context_, chords_, words_.size() * 4);
    plan_.write(&h, sizeof(Header));
    if (!words_.empty()) chords_.write(words_.data(), words_.size() * 4);
    bind();
    // Stamps: one kernel (phi and the offsets per node). Smooth: phi, then one kernel per act (each reads the
    // neighbours' values the act before it left). Grab: phi, then the advection (which reads phi around x - u).
    std::vector<std::array<std::uint32_t, 2>> passes{{mode, 0u}};  // mode, act
    if (mode == 2u) {
        passes.assign(1, {0u, 0u});
        for (std::uint32_t k = 0; k < h.counts[1]; ++k) passes.push_back({2u, k});
    } else if (mode == 4u) {
        passes.assign({{0u, 0u}, {4u, 0u}});
    }
    context_.submit_and_wait([&](VkCommandBuffer cmd) {
        for (std::size_t pass = 0; pass < passes.size(); ++pass) {
            const std::uint32_t m = passes[pass][0];
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline(m));
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_.get(), 0, 1, &set_, 0, nullptr);
            const std::size_t per = static_cast<std::size_t>(kMaxGroups) * kNodeGroup;
            for (std::size_t first = 0; first < count; first += per) {
                const std::uint32_t n = static_cast<std::uint32_t>(std::min(per, count - first));
                const Push push{static_cast<std::uint32_t>(first), n, 0.0f, passes[pass][1]};
                vkCmdPushConstants(cmd, pipeline_layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Push), &push);
                vkCmdDispatch(cmd, (n + kNodeGroup - 1) / kNodeGroup, 1, 1);
            }
            // phi before the offsets read it (and s0, s1 written by both, in order); then the host's reads.
            if (pass + 1 != passes.size())
                barrier(cmd, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT);
            else
                barrier(cmd, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT);
        }
    });
    ++stats_.submissions;
    ++stats_.fields;
    stats_.field_nodes += count;
    f.phi.resize(count);
    f.s0.resize(count);
    f.s1.resize(count);
    if (count == 0) return;
    phi_.read(f.phi.data(), count * 4);
    s0_.read(f.s0.data(), count * 4);
    s1_.read(f.s1.data(), count * 4);
}

void GpuClay::stamp_field(const TriDexel& model, ClayField& field, std::span<const ClayStamp> stamps,
                          const ClayStampParams& params) {
    check_model(model);
    host_field_ = !fits(field);
    if (host_field_) {
        ++stats_.host_fields;
        clay_cpu_kernel().stamp_field(model, field, stamps, params);
        return;
    }
    Header h;
    h.counts[1] = static_cast<std::uint32_t>(stamps.size());
    h.stamp_par[0] = params.r;
    h.stamp_par[1] = params.w;
    h.stamp_par[2] = params.reach2;
    h.stamp_par[3] = params.sign;
    std::memcpy(&h.counts[3], &params.rim_cap, sizeof(float));  // the rim's cap, float bits
    std::vector<float> words;  // per stamp: p, delta; n, 0
    words.reserve(8 * stamps.size());
    for (const ClayStamp& s : stamps)
        for (const float v : {s.p[0], s.p[1], s.p[2], s.delta, s.n[0], s.n[1], s.n[2], 0.0f}) words.push_back(v);
    build_field(field, 1u, h, words);
}

void GpuClay::smooth_field(const TriDexel& model, ClayField& field, std::span<const ClaySmoothParams> acts) {
    check_model(model);
    host_field_ = !fits(field);
    if (host_field_) {
        ++stats_.host_fields;
        clay_cpu_kernel().smooth_field(model, field, acts);
        return;
    }
    Header h;
    h.counts[1] = static_cast<std::uint32_t>(acts.size());
    std::vector<float> words;  // per act: point, r; normal, 0
    words.reserve(8 * acts.size());
    for (const ClaySmoothParams& p : acts)
        for (const float v : {p.point[0], p.point[1], p.point[2], p.r, p.normal[0], p.normal[1], p.normal[2], 0.0f})
            words.push_back(v);
    build_field(field, 2u, h, words);
}

void GpuClay::grab_field(const TriDexel& model, ClayField& field, const ClayGrabParams& params) {
    check_model(model);
    host_field_ = !fits(field);
    if (host_field_) {
        ++stats_.host_fields;
        clay_cpu_kernel().grab_field(model, field, params);
        return;
    }
    Header h;
    h.counts[1] = 1;
    h.stamp_par[0] = params.r;
    h.stamp_par[1] = params.core;
    const float words[8] = {params.anchor[0], params.anchor[1], params.anchor[2], 0.0f,
                            params.v[0],      params.v[1],      params.v[2],      0.0f};
    build_field(field, 4u, h, words);
}

void GpuClay::resample_rays(const TriDexel& model, const ClayField& f, std::span<const ClayMovedRay> moved,
                            float beta, ClayResampled* fixed, ClayResampled& var) {
    // The jobs: every moved ray this call re-samples, grouped by set (one pipeline per set), in order within a set.
    job_words_.clear();
    const std::uint32_t stride = 1 + 3 * options_.max_kernel_intervals;
    std::uint32_t jobs = 0, first[4] = {0, 0, 0, 0};
    for (std::uint32_t a = 0; a < 3; ++a) {
        first[a] = jobs;
        for (std::size_t k = 0; k < moved.size(); ++k) {
            const ClayMovedRay& m = moved[k];
            if (m.set != a || (!m.varies && !fixed)) continue;
            const std::uint32_t w[kJobWords] = {m.set,
                                                static_cast<std::uint32_t>(m.u),
                                                static_cast<std::uint32_t>(m.v),
                                                static_cast<std::uint32_t>(m.lo),
                                                static_cast<std::uint32_t>(m.hi),
                                                m.varies ? 1u : 0u,
                                                jobs * stride,
                                                static_cast<std::uint32_t>(k)};
            job_words_.insert(job_words_.end(), w, w + kJobWords);
            ++jobs;
        }
    }
    first[3] = jobs;
    if (jobs == 0) return;
    ensure(context_, jobs_, job_words_.size() * 4);
    ensure(context_, out_, static_cast<std::size_t>(jobs) * stride * 4);
    jobs_.write(job_words_.data(), job_words_.size() * 4);
    bind();
    VkPipeline kernels[3];
    for (std::uint32_t a = 0; a < 3; ++a) kernels[a] = first[a + 1] > first[a] ? pipeline(3u, a) : VK_NULL_HANDLE;
    context_.submit_and_wait([&](VkCommandBuffer cmd) {
        for (std::uint32_t a = 0; a < 3; ++a) {
            if (kernels[a] == VK_NULL_HANDLE) continue;
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, kernels[a]);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_layout_.get(), 0, 1, &set_, 0, nullptr);
            const std::uint32_t per = kMaxGroups * kRayGroup;
            for (std::uint32_t at = first[a]; at < first[a + 1]; at += per) {
                const std::uint32_t n = std::min(per, first[a + 1] - at);
                const Push push{at, n, beta, 0};
                vkCmdPushConstants(cmd, pipeline_layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Push), &push);
                vkCmdDispatch(cmd, (n + kRayGroup - 1) / kRayGroup, 1, 1);
            }
        }
        barrier(cmd, VK_ACCESS_HOST_READ_BIT, VK_PIPELINE_STAGE_HOST_BIT);
    });
    ++stats_.submissions;
    ++stats_.resamplings;
    stats_.rays_resampled += jobs;
    const std::uint32_t* out = static_cast<const std::uint32_t*>(out_.mapped());
    for (std::uint32_t j = 0; j < jobs; ++j) {
        const std::size_t k = job_words_[kJobWords * j + 7];
        const ClayMovedRay& m = moved[k];
        ClayResampled& r = m.varies ? var : *fixed;
        const std::vector<Interval>& old = model.sets[m.set].rays[m.index];
        std::vector<Interval>& ray = r.rays[k];
        const std::uint32_t* w = out + static_cast<std::size_t>(j) * stride;
        if (w[0] == kOverflow) {  // more intervals than the kernel writes: the CPU reference for this ray
            ++stats_.rays_on_host;
            clay_resample_ray(old, f, m.set, m.u, m.v, m.lo, m.hi, m.varies ? beta : 0.0f, ray);
        } else {
            ray.resize(w[0]);
            for (std::uint32_t i = 0; i < w[0]; ++i) {
                const std::uint32_t* iv = w + 1 + 3 * i;
                Interval& x = ray[i];
                std::memcpy(&x.enter, iv, 4);
                std::memcpy(&x.exit, iv + 1, 4);
                x.enter_material = static_cast<std::uint8_t>(iv[2] & 0xffu);
                x.exit_material = static_cast<std::uint8_t>((iv[2] >> 8) & 0xffu);
            }
        }
        clay_note_resampled(old, m, k, r);
    }
}

ClayStats GpuClay::resample(TriDexel& model, const ClayField& field, std::vector<RayImage>* before) {
    check_model(model);
    std::vector<ClayRayRef> written;
    ClayStats st;
    if (host_field_) {
        st = clay_resample_with(
            model, field, true, before,
            [&](std::span<const ClayMovedRay> moved, float beta, ClayResampled* fixed, ClayResampled& var) {
                clay_resample_on_cpu(model, field, moved, beta, fixed, var);
            },
            &written);
    } else {
        st = clay_resample_with(
            model, field, true, before,
            [&](std::span<const ClayMovedRay> moved, float beta, ClayResampled* fixed, ClayResampled& var) {
                resample_rays(model, field, moved, beta, fixed, var);
            },
            &written);
    }
    for (const ClayRayRef& r : written) sculptor_.store_mirror_ray(r.set, r.index);
    return st;
}

}  // namespace tridex::compute
