// renderer/output/stereo_output.cpp - quad support, box resampling and the compositions.
#include "renderer/output/stereo_output.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "renderer/output/anaglyph_tables.hpp"

namespace tridex::renderer {
namespace {

bool consistent(const Image& image) {
    return image.width > 0 && image.height > 0 &&
           image.rgba.size() == static_cast<std::size_t>(image.width) * image.height * 4;
}

void require_consistent(const Image& image, const char* what) {
    if (!consistent(image))
        throw Error(std::string("compose: the ") + what + " image is empty or inconsistent (" +
                    std::to_string(image.width) + "x" + std::to_string(image.height) + ", " +
                    std::to_string(image.rgba.size()) + " bytes)");
}

/// A width x height image with all bytes 0 (filled in completely by the caller).
Image blank(int width, int height) {
    return Image{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 4)};
}

/// Copies `src` into `dst` with its top-left corner at (x0, y0); src must fit.
void blit(Image& dst, const Image& src, int x0, int y0) {
    for (int y = 0; y < src.height; ++y)
        std::memcpy(dst.at(x0, y + y0), src.at(0, y), static_cast<std::size_t>(src.width) * 4);
}

/// 1-D box resampling weights: for each output index, (first source index, coverage per source index).
struct BoxTaps {
    std::vector<int> first;
    std::vector<std::vector<double>> weights;  // sum to 1 per output index
};

BoxTaps box_taps(int from, int to) {
    BoxTaps taps;
    taps.first.resize(to);
    taps.weights.resize(to);
    const double step = static_cast<double>(from) / to;  // source pixels per output pixel
    for (int i = 0; i < to; ++i) {
        const double a = i * step, b = (i + 1) * step;
        const int first = static_cast<int>(std::floor(a));
        const int last = std::min(from - 1, static_cast<int>(std::ceil(b)) - 1);
        taps.first[i] = first;
        for (int s = first; s <= last; ++s) {
            const double cover = std::min(b, s + 1.0) - std::max(a, static_cast<double>(s));
            taps.weights[i].push_back(cover / step);
        }
    }
    return taps;
}

/// Rec. 601 luma of an 8-bit RGB pixel, rounded half up, in exact integer arithmetic.
std::uint8_t luma601(const std::uint8_t* p) {
    return static_cast<std::uint8_t>((299 * p[0] + 587 * p[1] + 114 * p[2] + 500) / 1000);
}

Image anaglyph(const Image& left, const Image& right, AnaglyphMethod method) {
    const SrgbCodeTables& tables = srgb_code_tables();
    const AnaglyphMatrices& m = dubois_matrices();
    Image out = blank(left.width, left.height);
    const std::size_t n = out.rgba.size();
    const std::uint8_t* l = left.rgba.data();
    const std::uint8_t* r = right.rgba.data();
    std::uint8_t* o = out.rgba.data();
    for (std::size_t i = 0; i < n; i += 4) {
        switch (method) {
        case AnaglyphMethod::kDubois: {
            const double ll[3] = {tables.to_linear[l[i]], tables.to_linear[l[i + 1]], tables.to_linear[l[i + 2]]};
            const double rl[3] = {tables.to_linear[r[i]], tables.to_linear[r[i + 1]], tables.to_linear[r[i + 2]]};
            for (int c = 0; c < 3; ++c) {
                double v = 0.0;
                for (int k = 0; k < 3; ++k) v += m.left[c][k] * ll[k] + m.right[c][k] * rl[k];
                o[i + c] = srgb_encode_code(v);  // below 0 -> 0, above 1 -> 255
            }
            break;
        }
        case AnaglyphMethod::kColour:
            o[i] = l[i];
            o[i + 1] = r[i + 1];
            o[i + 2] = r[i + 2];
            break;
        case AnaglyphMethod::kGray:
            o[i] = luma601(l + i);
            o[i + 1] = o[i + 2] = luma601(r + i);
            break;
        }
        o[i + 3] = 255;
    }
    return out;
}

}  // namespace

bool needs_both_eyes(StereoOutput output) { return output != StereoOutput::kMono; }

std::pair<int, int> output_size(StereoOutput output, int eye_width, int eye_height) {
    if (eye_width < 1 || eye_height < 1)
        throw Error("output_size: eye image size must be at least 1x1 (got " + std::to_string(eye_width) + "x" +
                    std::to_string(eye_height) + ")");
    switch (output) {
    case StereoOutput::kSideBySide: return {2 * eye_width, eye_height};
    case StereoOutput::kTopBottom: return {eye_width, 2 * eye_height};
    default: return {eye_width, eye_height};
    }
}

std::pair<int, int> eye_size_for_output(StereoOutput output, int output_width, int output_height) {
    if (output_width < 1 || output_height < 1)
        throw Error("eye_size_for_output: the output image must be at least 1x1 (got " + std::to_string(output_width) +
                    "x" + std::to_string(output_height) + ")");
    switch (output) {
    case StereoOutput::kSideBySide: return {std::max(1, output_width / 2), output_height};
    case StereoOutput::kTopBottom: return {output_width, std::max(1, output_height / 2)};
    default: return {output_width, output_height};
    }
}

std::vector<StereoOutput> supported_outputs(std::uint32_t max_image_array_layers) {
    std::vector<StereoOutput> v;
    for (StereoOutput o : all_stereo_outputs())
        if (o != StereoOutput::kQuad || max_image_array_layers >= 2) v.push_back(o);
    return v;
}

OutputSupport check_output_support(StereoOutput output, std::uint32_t max_image_array_layers) {
    if (output != StereoOutput::kQuad || max_image_array_layers >= 2) return {};
    std::string working;
    for (StereoOutput o : supported_outputs(max_image_array_layers)) {
        if (!working.empty()) working += ", ";
        working += to_string(o);
    }
    return OutputSupport{false, "stereo output 'quad' needs a swapchain with 2 image layers but the surface reports "
                                "maxImageArrayLayers = " +
                                    std::to_string(max_image_array_layers) + "; outputs that will work: " + working};
}

Image resample_box(const Image& image, int new_width, int new_height) {
    if (!consistent(image))
        throw Error("resample_box: the image is empty or inconsistent (" + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + ")");
    if (new_width < 1 || new_height < 1)
        throw Error("resample_box: new size must be at least 1x1 (got " + std::to_string(new_width) + "x" +
                    std::to_string(new_height) + ")");
    if (new_width == image.width && new_height == image.height) return image;
    // Exact 2:1 squeezes (the half-resolution outputs of even-sized eyes): pair averages, rounded half up.
    if (2 * new_width == image.width && new_height == image.height) {
        Image out = blank(new_width, new_height);
        const std::uint8_t* src = image.rgba.data();
        std::uint8_t* dst = out.rgba.data();
        for (std::size_t px = 0, n = out.rgba.size() / 4; px < n; ++px, src += 8, dst += 4)
            for (int c = 0; c < 4; ++c) dst[c] = static_cast<std::uint8_t>((src[c] + src[c + 4] + 1) / 2);
        return out;
    }
    if (new_width == image.width && 2 * new_height == image.height) {
        Image out = blank(new_width, new_height);
        const std::size_t row = static_cast<std::size_t>(image.width) * 4;
        for (int y = 0; y < new_height; ++y) {
            const std::uint8_t* a = image.rgba.data() + 2 * y * row;
            const std::uint8_t* b = a + row;
            std::uint8_t* dst = out.rgba.data() + y * row;
            for (std::size_t i = 0; i < row; ++i) dst[i] = static_cast<std::uint8_t>((a[i] + b[i] + 1) / 2);
        }
        return out;
    }
    const BoxTaps tx = box_taps(image.width, new_width);
    const BoxTaps ty = box_taps(image.height, new_height);
    Image out = blank(new_width, new_height);
    for (int y = 0; y < new_height; ++y) {
        for (int x = 0; x < new_width; ++x) {
            double acc[4] = {0.0, 0.0, 0.0, 0.0};
            for (std::size_t j = 0; j < ty.weights[y].size(); ++j) {
                for (std::size_t i = 0; i < tx.weights[x].size(); ++i) {
                    const double w = ty.weights[y][j] * tx.weights[x][i];
                    const std::uint8_t* p =
                        image.at(tx.first[x] + static_cast<int>(i), ty.first[y] + static_cast<int>(j));
                    for (int c = 0; c < 4; ++c) acc[c] += w * p[c];
                }
            }
            std::uint8_t* o = out.at(x, y);
            // The 1e-9 guards exact halves (x.5) against weights that sum to 1 - ulp: halves round up.
            for (int c = 0; c < 4; ++c)
                o[c] = static_cast<std::uint8_t>(std::clamp(std::floor(acc[c] + 0.5 + 1e-9), 0.0, 255.0));
        }
    }
    return out;
}

Image compose(StereoOutput output, const Image& left, const Image& right, const ComposeOptions& options) {
    require_consistent(left, "left");
    if (output == StereoOutput::kMono) return left;
    require_consistent(right, "right");
    if (left.width != right.width || left.height != right.height)
        throw Error("compose: the eye images differ in size (" + std::to_string(left.width) + "x" +
                    std::to_string(left.height) + " vs " + std::to_string(right.width) + "x" +
                    std::to_string(right.height) + ")");
    const Image& first = options.swap_eyes ? right : left;   // left half / top half / slot 0
    const Image& second = options.swap_eyes ? left : right;  // right half / bottom half / slot 1
    const int w = left.width, h = left.height;
    switch (output) {
    case StereoOutput::kQuad:
    case StereoOutput::kFrameSequential:
        if (options.eye_slot != 0 && options.eye_slot != 1)
            throw Error("compose: eye_slot must be 0 (left) or 1 (right), got " + std::to_string(options.eye_slot));
        return options.eye_slot == 0 ? first : second;
    case StereoOutput::kSideBySide: {
        Image out = blank(2 * w, h);
        blit(out, first, 0, 0);
        blit(out, second, w, 0);
        return out;
    }
    case StereoOutput::kTopBottom: {
        Image out = blank(w, 2 * h);
        blit(out, first, 0, 0);
        blit(out, second, 0, h);
        return out;
    }
    case StereoOutput::kSideBySideHalf: {
        if (w < 2) throw Error("compose: side-by-side-half needs eye images at least 2 pixels wide");
        Image out = blank(w, h);
        blit(out, resample_box(first, w / 2, h), 0, 0);
        blit(out, resample_box(second, w - w / 2, h), w / 2, 0);
        return out;
    }
    case StereoOutput::kTopBottomHalf: {
        if (h < 2) throw Error("compose: top-bottom-half needs eye images at least 2 pixels high");
        Image out = blank(w, h);
        blit(out, resample_box(first, w, h / 2), 0, 0);
        blit(out, resample_box(second, w, h - h / 2), 0, h / 2);
        return out;
    }
    case StereoOutput::kAnaglyph: return anaglyph(first, second, options.anaglyph);
    case StereoOutput::kMono: break;  // handled above
    }
    return left;
}

}  // namespace tridex::renderer
