// compute/tools/clay_kernel.cpp - the CPU reference ClayKernel.
#include "compute/tools/clay_kernel.hpp"

namespace tridex::compute {
namespace {

class CpuClayKernel final : public ClayKernel {
public:
    void stamp_field(const TriDexel& model, ClayField& field, std::span<const ClayStamp> stamps,
                     const ClayStampParams& params) override {
        clay_build_phi(model, field);
        clay_stamp_offsets(model, field, stamps, params);
    }
    void smooth_field(const TriDexel& model, ClayField& field, std::span<const ClaySmoothParams> acts) override {
        clay_build_phi(model, field);
        clay_smooth_offsets(model, field, acts);
    }
    void grab_field(const TriDexel& model, ClayField& field, const ClayGrabParams& params) override {
        clay_build_phi(model, field);
        clay_grab_offsets(model, field, params);
    }
    ClayStats resample(TriDexel& model, const ClayField& field, std::vector<RayImage>* before) override {
        return clay_resample(model, field, true, before);
    }
};

}  // namespace

ClayKernel& clay_cpu_kernel() {
    static CpuClayKernel kernel;
    return kernel;
}

}  // namespace tridex::compute
