// renderer/window/window_blit_layout.cpp - eye rectangles in the swapchain image for each stereo output.
#include "renderer/window/window_blit_layout.hpp"

#include <string>

#include "core/error.hpp"

namespace tridex::renderer {

BlitPlan plan_blits(StereoOutput output, int width, int height, bool swap_eyes, int frame_eye) {
    if (width < 1 || height < 1)
        throw Error("plan_blits: swapchain size " + std::to_string(width) + "x" + std::to_string(height) +
                    " must be at least 1x1");
    if (frame_eye != 0 && frame_eye != 1) throw Error("plan_blits: frame_eye must be 0 or 1");
    const int first = swap_eyes ? 1 : 0, second = 1 - first;
    BlitPlan plan;
    switch (output) {
        case StereoOutput::kSideBySide:
        case StereoOutput::kSideBySideHalf: {
            if (width < 2) throw Error("plan_blits: side-by-side needs a swapchain at least 2 pixels wide");
            const int split = width / 2;
            plan.count = 2;
            plan.blits[0] = EyeBlit{first, 0, 0, 0, split, height};
            plan.blits[1] = EyeBlit{second, 0, split, 0, width, height};
            return plan;
        }
        case StereoOutput::kTopBottom:
        case StereoOutput::kTopBottomHalf: {
            if (height < 2) throw Error("plan_blits: top-bottom needs a swapchain at least 2 pixels high");
            const int split = height / 2;
            plan.count = 2;
            plan.blits[0] = EyeBlit{first, 0, 0, 0, width, split};
            plan.blits[1] = EyeBlit{second, 0, 0, split, width, height};
            return plan;
        }
        case StereoOutput::kQuad:
            plan.count = 2;
            plan.blits[0] = EyeBlit{first, 0, 0, 0, width, height};
            plan.blits[1] = EyeBlit{second, 1, 0, 0, width, height};
            return plan;
        case StereoOutput::kFrameSequential:
            plan.count = 1;
            plan.blits[0] = EyeBlit{frame_eye, 0, 0, 0, width, height};
            return plan;
        case StereoOutput::kMono:
            plan.count = 1;
            plan.blits[0] = EyeBlit{0, 0, 0, 0, width, height};
            return plan;
        case StereoOutput::kAnaglyph: break;
    }
    throw Error("plan_blits: stereo output '" + std::string(to_string(output)) +
                "' mixes pixels and has no blit plan; compose it (AnaglyphPass on the GPU, compose() on the CPU) "
                "and present the result");
}

std::pair<int, int> eye_size_for(StereoOutput output, int width, int height) {
    if (output == StereoOutput::kAnaglyph) {
        if (width < 1 || height < 1) throw Error("eye_size_for: the output size must be at least 1x1");
        return {width, height};
    }
    const BlitPlan plan = plan_blits(output, width, height);  // validates the size for the output
    const EyeBlit& b = plan.blits[0];
    return {b.x1 - b.x0, b.y1 - b.y0};
}

std::uint32_t swapchain_layers(StereoOutput output) { return output == StereoOutput::kQuad ? 2u : 1u; }

}  // namespace tridex::renderer
