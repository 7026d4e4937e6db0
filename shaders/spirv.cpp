// shaders/spirv.cpp - name -> SPIR-V lookup over the headers glslangValidator generated.
#include "shaders/spirv.hpp"

#include <string>

#include "core/error.hpp"
#include "shaders/spirv_table.inc"

namespace tridex::shaders {
namespace {

struct Entry {
    std::string_view name;
    const std::uint32_t* words;
    std::size_t count;
};

constexpr Entry kTable[] = {TRIDEX_SHADER_TABLE};

}  // namespace

std::span<const std::uint32_t> spirv(std::string_view name) {
    for (const Entry& e : kTable)
        if (e.name == name) return {e.words, e.count};
    throw Error("shaders: no embedded SPIR-V module named '" + std::string(name) +
                "' (register it in shaders/CMakeLists.txt)");
}

std::vector<std::string_view> names() {
    std::vector<std::string_view> out;
    for (const Entry& e : kTable) out.push_back(e.name);
    return out;
}

}  // namespace tridex::shaders
