// renderer/camera/stereo_output_mode.cpp - the names of the stereo output modes and anaglyph mixings.
#include "renderer/camera/stereo_output_mode.hpp"

#include <array>

#include "core/error.hpp"

namespace tridex::renderer {
namespace {

struct OutputName {
    StereoOutput output;
    std::string_view name;
};

constexpr std::array<OutputName, 8> kOutputNames{{
    {StereoOutput::kQuad, "quad"},
    {StereoOutput::kFrameSequential, "frame-sequential"},
    {StereoOutput::kSideBySide, "side-by-side"},
    {StereoOutput::kSideBySideHalf, "side-by-side-half"},
    {StereoOutput::kTopBottom, "top-bottom"},
    {StereoOutput::kTopBottomHalf, "top-bottom-half"},
    {StereoOutput::kAnaglyph, "anaglyph"},
    {StereoOutput::kMono, "mono"},
}};

}  // namespace

std::string_view to_string(StereoOutput output) {
    for (const OutputName& n : kOutputNames)
        if (n.output == output) return n.name;
    return "unknown";
}

std::string_view to_string(AnaglyphMethod method) {
    switch (method) {
    case AnaglyphMethod::kDubois: return "dubois";
    case AnaglyphMethod::kColour: return "colour";
    case AnaglyphMethod::kGray: return "gray";
    }
    return "unknown";
}

const std::vector<StereoOutput>& all_stereo_outputs() {
    static const std::vector<StereoOutput> all = [] {
        std::vector<StereoOutput> v;
        for (const OutputName& n : kOutputNames) v.push_back(n.output);
        return v;
    }();
    return all;
}

std::string stereo_output_names() {
    std::string s;
    for (const OutputName& n : kOutputNames) {
        if (!s.empty()) s += ", ";
        s += n.name;
    }
    return s;
}

StereoOutput parse_stereo_output(const std::string& name) {
    for (const OutputName& n : kOutputNames)
        if (n.name == name) return n.output;
    throw Error("unknown stereo output '" + name + "'; valid outputs: " + stereo_output_names());
}

AnaglyphMethod parse_anaglyph_method(const std::string& name) {
    for (AnaglyphMethod m : {AnaglyphMethod::kDubois, AnaglyphMethod::kColour, AnaglyphMethod::kGray})
        if (to_string(m) == name) return m;
    throw Error("unknown anaglyph method '" + name + "'; valid methods: dubois, colour, gray");
}

}  // namespace tridex::renderer
