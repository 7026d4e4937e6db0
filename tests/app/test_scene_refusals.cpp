// Tests of the scene reader's refusals found by fuzzing (tests/fuzz/fuzz_scene.cpp): each holds the input that was
// refused badly, as bytes, and checks the refusal is one printable line naming the file and the field.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "app/scene/run_scene.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

/// The refusal of run_scene_from_json for the scene text `text` (named "scene.json"); empty when accepted.
std::string refusal_of(const std::string& text) {
    try {
        (void)run_scene_from_json(nlohmann::json::parse(text), "scene.json", ".");
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

/// True when every byte of `s` is printable ASCII.
bool printable_line(const std::string& s) {
    for (const char c : s)
        if (c < 0x20 || c == 0x7f) return false;
    return true;
}

TEST(SceneRefusals, AnUnknownKeyIsQuotedPrintably) {
    // The fuzzer's input, reduced: a device block whose key "profile" has DEL bytes (0x7f) and an escape character
    // (U+001B, escaped in the JSON text) in it; the refusal quoted the key raw.
    const std::string message = refusal_of("{\"device\": {\"driver\": \"simulated\", \"profil\x7f\x7f\\u001b[2Je\": \"wand\"}}");
    ASSERT_FALSE(message.empty()) << "the scene was accepted";
    EXPECT_EQ(message.rfind("scene.json: field 'device.profil\\x7f\\x7f\\x1b[2Je': unknown field", 0), 0u) << message;
    EXPECT_TRUE(printable_line(message)) << message;
}

TEST(SceneRefusals, AMissingStudySceneIsNamedPrintably) {
    // The fuzzer's input, reduced: a study scene file name with a DEL byte (0x7f) that names no file; the study
    // scene reader's refusal quoted the path raw. The scene reader now says it is missing, through its field.
    const std::string message = refusal_of("{\"study\": {\"scene\": \"study\x7ftube_scene.json\", \"model\": \"test\"}}");
    ASSERT_FALSE(message.empty()) << "the scene was accepted";
    EXPECT_EQ(message, "scene.json: field 'study.scene': no such file: ./study\\x7ftube_scene.json");
    EXPECT_TRUE(printable_line(message)) << message;
}

}  // namespace
}  // namespace tridex::app
