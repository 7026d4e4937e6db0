// compute/gpu/gpu_clay.hpp - the clay tools (push, pull, smooth, grab) on the GPU-resident model: the node field and
// the re-sampling of the rays in Vulkan compute (shaders/clay_field.comp), bit for bit the CPU reference.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "compute/gpu/gpu_sculptor.hpp"
#include "compute/tools/clay_kernel.hpp"
#include "compute/tools/clay_resample.hpp"
#include "gpu/buffer.hpp"
#include "gpu/context.hpp"
#include "gpu/shader_module.hpp"
#include "gpu/unique_handle.hpp"

namespace tridex::compute {

/// Options of a GpuClay.
struct GpuClayOptions {
    /// Most intervals the kernel writes for one re-sampled ray (1..120); a ray that needs more is handed back and
    /// re-sampled on the host with the CPU reference (clay_resample_ray) for that ray only. Small values exercise that
    /// path (tests).
    std::uint32_t max_kernel_intervals = 16;
    /// Most nodes a field box may have on the GPU; 0 = what one storage binding holds (maxStorageBufferRange / 4).
    /// A bigger box runs its field and re-sampling on the CPU reference (GpuClayStats::host_fields). Small values
    /// exercise that path (tests).
    std::size_t max_field_nodes = 0;
};

/// Counters of a GpuClay since it was created.
struct GpuClayStats {
    std::uint64_t fields = 0;          ///< fields built on the GPU (one per push, pull or smooth piece that acts)
    std::uint64_t field_nodes = 0;     ///< box nodes the field kernels computed, summed
    std::uint64_t resamplings = 0;     ///< re-sampling submissions (one to three per field)
    std::uint64_t rays_resampled = 0;  ///< rays the kernel re-sampled, summed over submissions
    std::uint64_t rays_on_host = 0;    ///< rays handed back (over max_kernel_intervals) and redone on the host
    std::uint64_t host_fields = 0;     ///< fields whose box exceeds one storage binding, run on the CPU reference
    std::uint64_t submissions = 0;     ///< GPU submissions (each waits for its fence)
};

/// A ClayKernel (compute/tools/clay_kernel.hpp) on a GpuSculptor's model. What runs where, per push, pull or smooth
/// piece (apply_clay drives it):
/// - host, on the sculptor's CPU mirror: the stamps' contacts (clay_contact: a 4 x 4 x 4 node field and the nearest
///   crossing per stamp, a handful of values), the field's box, region and chords (O(rays through the box)), the
///   moved nodes and rays, the beta solve (ClayVolumeModel's prediction from the field and the mirror's rays, and the
///   measured volume: sums in double over the moved rays, in the CPU's order) and the `before` images;
/// - GPU, one submission: phi at every node of the box from the slabs (NaN off the region, as clay_build_phi) and
///   s0, s1 from the stamps (one kernel), or phi and then the smooth's Laplacian or the grab's advection (two); the
///   host copies phi, s0, s1
///   back (the beta solve reads them);
/// - GPU, one submission per beta tried (one to three; almost always one): every moved ray re-sampled from the slabs and the field into
///   an output list; the host compares it with the old ray and sums its length (clay_note_resampled);
/// - host: the chosen rays into the mirror (dirty tiles marked there) and into the slabs
///   (GpuSculptor::store_mirror_ray, compacting a full pool).
/// The kernels repeat the CPU reference's float arithmetic in its order without contraction, so the model, the
/// `before` images and the ClayStats equal the CPU reference's bit for bit (tests/compute/test_gpu_clay.cpp).
/// A box over maxStorageBufferRange / 4 nodes (a tool of hundreds of cells; or GpuClayOptions::max_field_nodes) runs
/// its field and re-sampling on the CPU reference instead (counted in host_fields), with the same result.
/// Not thread-safe; the Context and the sculptor must outlive it, and the model handed to its methods must be the
/// sculptor's mirror.
class GpuClay final : public ClayKernel {
public:
    /// Makes the seven pipelines of shaders/clay_field.comp on `context` (the sculptor's; tens of ms each on lavapipe)
    /// and runs each once empty, so that no clay operation waits for a kernel to be prepared. Throws tridex::Error
    /// when the device offers fewer than 21 storage buffers per stage, on a bad option, or on a Vulkan failure.
    GpuClay(const gpu::Context& context, GpuSculptor& sculptor, const GpuClayOptions& options = {});
    ~GpuClay() override;
    GpuClay(const GpuClay&) = delete;
    GpuClay& operator=(const GpuClay&) = delete;

    /// See ClayKernel. Throw tridex::Error when `model` is not the sculptor's mirror, on a device failure, or (resample)
    /// when a ray needs more intervals than the slabs hold (GpuSculptor::store_mirror_ray; the mirror is then ahead of
    /// the slabs and the caller should stop sculpting).
    void stamp_field(const TriDexel& model, ClayField& field, std::span<const ClayStamp> stamps,
                     const ClayStampParams& params) override;
    void smooth_field(const TriDexel& model, ClayField& field, std::span<const ClaySmoothParams> acts) override;
    void grab_field(const TriDexel& model, ClayField& field, const ClayGrabParams& params) override;
    ClayStats resample(TriDexel& model, const ClayField& field, std::vector<RayImage>* before) override;

    /// This kernel's ClayResampleFn (clay_resample.hpp): the moved rays of `field` (built by this kernel's
    /// stamp_field or smooth_field) re-sampled at beta on the GPU from the slabs, those with varies into `var`, the
    /// others into `fixed` when it is not null; slots sized by the caller. Bit for bit clay_resample_on_cpu on the
    /// mirror. Throws tridex::Error as resample.
    void resample_rays(const TriDexel& model, const ClayField& field, std::span<const ClayMovedRay> moved, float beta,
                       ClayResampled* fixed, ClayResampled& var);

    /// Counters since creation.
    const GpuClayStats& stats() const { return stats_; }

private:
    struct Header;
    void check_model(const TriDexel& model) const;
    bool fits(const ClayField& field) const;
    void build_field(ClayField& field, std::uint32_t mode, Header& header, std::span<const float> stamps);
    void bind();
    VkPipeline pipeline(std::uint32_t mode, std::uint32_t set = 0);

    const gpu::Context& context_;
    GpuSculptor& sculptor_;
    GpuClayOptions options_;
    GpuClayStats stats_;
    gpu::UniqueDescriptorSetLayout set_layout_;
    gpu::UniquePipelineLayout pipeline_layout_;
    gpu::UniqueShaderModule module_;
    gpu::UniquePipeline pipelines_[7];  // MODE 0 phi, 1 stamps, 2 smooth, 3 + set: rays of that set, 6: MODE 4 grab
    gpu::UniqueDescriptorPool descriptor_pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
    gpu::Buffer phi_, s0_, s1_, chords_, jobs_, out_;
    gpu::Buffer plan_;  // the Header: a uniform buffer
    bool host_field_ = false;  // the last field was built on the CPU reference (too big a box)
    std::vector<std::uint32_t> words_;
    std::vector<std::uint32_t> job_words_;
};

}  // namespace tridex::compute
