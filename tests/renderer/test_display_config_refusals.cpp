// Tests of the display config reader's refusals found by fuzzing (tests/fuzz/fuzz_display_config.cpp): each holds
// the input that was refused badly, as bytes, and checks the refusal is one printable line naming the field.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "renderer/camera/display_config.hpp"

namespace tridex::renderer {
namespace {

TEST(DisplayConfigRefusals, AnUnknownKeyIsQuotedPrintably) {
    // The fuzzer's input, reduced: the key "default_head_m" with a control character (U+0001, escaped in the JSON
    // text) and DEL (a raw byte) for the '_'; the refusal quoted the key raw.
    std::string message;
    try {
        (void)display_config_from_json(nlohmann::json::parse("{\"default\\u0001\x7fhead_m\": [0, 0, 1]}"), "wall.json");
    } catch (const Error& e) {
        message = e.what();
    }
    ASSERT_FALSE(message.empty()) << "the config was accepted";
    EXPECT_EQ(message.rfind("wall.json: field 'default\\x01\\x7fhead_m': unknown field", 0), 0u) << message;
    for (const char c : message) EXPECT_TRUE(c >= 0x20 && c != 0x7f) << message;
}

}  // namespace
}  // namespace tridex::renderer
