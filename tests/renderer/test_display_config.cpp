// Tests of DisplayConfig: presets, JSON round trip, corner squaring, and every bad field named in the error.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "renderer/camera/display_config.hpp"

namespace tridex::renderer {
namespace {

std::filesystem::path temp_dir() {
    const auto dir = std::filesystem::current_path() / "display_config_out";
    std::filesystem::create_directories(dir);
    return dir;
}

std::string write_file(const std::string& name, const std::string& text) {
    const auto path = (temp_dir() / name).string();
    std::ofstream(path) << text;
    return path;
}

/// The error message of loading `text` from a file called `name`, or "" when it loads.
std::string load_error(const std::string& name, const std::string& text) {
    const std::string path = write_file(name, text);
    try {
        load_display_config(path);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

void expect_vec(const Vec3& a, const Vec3& b, double tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(DisplayConfig, PresetsArePowerWallAndDesk) {
    const DisplayConfig wall = DisplayConfig::powerwall();
    EXPECT_NEAR(wall.screen.width(), 3.048, 1e-12);   // 10 ft
    EXPECT_NEAR(wall.screen.height(), 2.286, 1e-12);  // 7.5 ft
    EXPECT_EQ(wall.stereo, StereoOutput::kFrameSequential);
    EXPECT_DOUBLE_EQ(wall.refresh_hz, 120.0);
    const DisplayConfig desk = DisplayConfig::desktop();
    EXPECT_NEAR(desk.screen.width(), 0.53, 1e-12);
    EXPECT_NEAR(desk.screen.height(), 0.30, 1e-12);
    EXPECT_DOUBLE_EQ(desk.default_head_m.z, 0.6);
    EXPECT_EQ(desk.stereo, StereoOutput::kMono);  // anaglyph by choice at a desk
    EXPECT_FALSE(desk.resolution_given);  // a desk window is sized to its monitor
    EXPECT_NO_THROW(validate_display_config(wall, "wall"));
    EXPECT_NO_THROW(validate_display_config(desk, "desk"));
}

TEST(DisplayConfig, SaveLoadRoundTripIsExact) {
    DisplayConfig c = DisplayConfig::powerwall();
    c.screen = Screen{Vec3(-1.1, 0.2, -0.3), Vec3(1.9, 0.2, -0.3), Vec3(-1.1, 2.45, -0.3)};
    c.stereo = StereoOutput::kTopBottomHalf;
    c.anaglyph = AnaglyphMethod::kGray;
    c.eye_separation_m = 0.0632;
    c.swap_eyes = true;
    c.ambient_occlusion = false;
    c.refresh_hz = 119.88;
    c.width_px = 1400;
    c.height_px = 1050;
    c.default_head_m = Vec3(0.1, 1.6, 2.5);
    const auto path = (temp_dir() / "roundtrip.json").string();
    save_display_config(path, c);
    const DisplayConfig d = load_display_config(path);
    EXPECT_EQ(d.screen.lower_left, c.screen.lower_left);
    EXPECT_EQ(d.screen.lower_right, c.screen.lower_right);
    EXPECT_EQ(d.screen.upper_left, c.screen.upper_left);
    EXPECT_EQ(d.stereo, c.stereo);
    EXPECT_EQ(d.anaglyph, c.anaglyph);
    EXPECT_EQ(d.eye_separation_m, c.eye_separation_m);
    EXPECT_EQ(d.swap_eyes, c.swap_eyes);
    EXPECT_EQ(d.ambient_occlusion, c.ambient_occlusion);
    EXPECT_EQ(d.refresh_hz, c.refresh_hz);
    EXPECT_EQ(d.width_px, c.width_px);
    EXPECT_EQ(d.height_px, c.height_px);
    EXPECT_EQ(d.default_head_m, c.default_head_m);
}

TEST(DisplayConfig, MissingFieldsComeFromThePresetAndScreenNamesWork) {
    const std::string path = write_file("wall.json", R"({"preset": "powerwall", "swap_eyes": true})");
    const DisplayConfig c = load_display_config(path);
    EXPECT_EQ(c.stereo, StereoOutput::kFrameSequential);
    EXPECT_TRUE(c.swap_eyes);
    EXPECT_TRUE(c.ambient_occlusion);  // on unless the file says otherwise
    EXPECT_EQ(c.screen.lower_left, Screen::powerwall().lower_left);
    const DisplayConfig d = display_config_from_json(nlohmann::json::parse(R"({"screen": "powerwall",
        "default_head_m": [0, 1.7, 3], "stereo": "side-by-side"})"), "inline");
    EXPECT_EQ(d.screen.upper_left, Screen::powerwall().upper_left);
    EXPECT_EQ(d.stereo, StereoOutput::kSideBySide);
    EXPECT_DOUBLE_EQ(d.refresh_hz, 60.0);  // desktop preset
    const DisplayConfig e = display_config_from_json(nlohmann::json::object(), "empty");
    EXPECT_EQ(e.screen.lower_right, Screen::desktop_monitor().lower_right);
}

TEST(DisplayConfig, SlightlySkewedMeasuredCornersAreSquaredUp) {
    // upper_left 1 mm too far right on a 0.4 x 0.3 m screen (|cos| = 0.0033): moved back within the plane.
    const auto j = nlohmann::json::parse(R"({"screen": {"lower_left": [-0.2, -0.15, 0],
        "lower_right": [0.2, -0.15, 0], "upper_left": [-0.199, 0.15, 0]}, "default_head_m": [0, 0, 0.5]})");
    const DisplayConfig c = display_config_from_json(j, "measured.json");
    expect_vec(c.screen.upper_left, Vec3(-0.2, 0.15, 0.0), 1e-15);
    // 5 mm over 0.3 m (|cos| = 0.0167) is refused.
    auto bad = j;
    bad["screen"]["upper_left"] = {-0.195, 0.15, 0.0};
    try {
        display_config_from_json(bad, "measured.json");
        FAIL() << "no throw";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("measured.json: field 'screen.upper_left': "), std::string::npos) << m;
        EXPECT_NE(m.find("right angle"), std::string::npos) << m;
    }
}

TEST(DisplayConfig, EveryBadFieldIsNamedWithTheFile) {
    struct Case {
        const char* json;
        const char* field;
    };
    const Case cases[] = {
        {R"({"screen": {"lower_left": [0, 0], "lower_right": [1, 0, 0], "upper_left": [0, 1, 0]}})",
         "screen.lower_left"},
        {R"({"screen": {"lower_left": [0, 0, 0], "lower_right": [0, 0, 0], "upper_left": [0, 1, 0]}})",
         "screen.lower_right"},
        {R"({"screen": {"lower_left": [0, 0, 0], "lower_right": [1, 0, 0], "upper_left": [0, 0, 0]}})",
         "screen.upper_left"},
        {R"({"screen": {"lower_left": [0, 0, 0], "lower_right": [1, 0, 0]}})", "screen.upper_left"},
        {R"({"screen": {"lower_left": [0, 0, 0], "lower_right": [1, 0, 0], "upper_left": [0, "1", 0]}})",
         "screen.upper_left"},
        {R"({"screen": {"lower_left": [0, 0, 0], "lower_right": [1, 0, 0], "upper_left": [0, 1, 0], "centre": 1}})",
         "screen.centre"},
        {R"({"screen": "cave"})", "screen"},
        {R"({"screen": 3})", "screen"},
        {R"({"stereo": "sbs"})", "stereo"},
        {R"({"stereo": 2})", "stereo"},
        {R"({"anaglyph": "amber-blue"})", "anaglyph"},
        {R"({"eye_separation_m": -0.01})", "eye_separation_m"},
        {R"({"eye_separation_m": 65})", "eye_separation_m"},
        {R"({"eye_separation_m": "65mm"})", "eye_separation_m"},
        {R"({"swap_eyes": 1})", "swap_eyes"},
        {R"({"ambient_occlusion": "off"})", "ambient_occlusion"},
        {R"({"refresh_hz": 0})", "refresh_hz"},
        {R"({"refresh_hz": 5000})", "refresh_hz"},
        {R"({"resolution": [1920]})", "resolution"},
        {R"({"resolution": [1920.5, 1080]})", "resolution"},
        {R"({"resolution": [0, 1080]})", "resolution"},
        {R"({"resolution": [1920, 100000]})", "resolution"},
        {R"({"default_head_m": [0, 0, -0.6]})", "default_head_m"},
        {R"({"default_head_m": [0, 0]})", "default_head_m"},
        {R"({"preset": "cave"})", "preset"},
        {R"({"eye_seperation_m": 0.065})", "eye_seperation_m"},
    };
    for (const Case& c : cases) {
        const std::string m = load_error("bad.json", c.json);
        const std::string want = "bad.json: field '" + std::string(c.field) + "': ";
        EXPECT_NE(m.find(want), std::string::npos) << c.json << " -> " << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;  // one line
    }
}

TEST(DisplayConfig, UnreadableOrMalformedFilesAreNamed) {
    const std::string missing = (temp_dir() / "no_such_file.json").string();
    try {
        load_display_config(missing);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
    }
    EXPECT_NE(load_error("broken.json", "{\"stereo\": ").find("broken.json: not valid JSON"), std::string::npos);
    EXPECT_NE(load_error("huge.json", "{\"stereo\": \"anaglyph\",\n \"refresh_hz\": 1e400}")
                  .find("huge.json: not valid JSON: number overflow at line 2, column 16, field 'refresh_hz': '1e400' "
                        "is beyond a double's range"),
              std::string::npos)
        << load_error("huge.json", "{\"stereo\": \"anaglyph\",\n \"refresh_hz\": 1e400}");
    EXPECT_NE(load_error("array.json", "[1, 2]").find("array.json: a display config must be a JSON object"),
              std::string::npos);
    DisplayConfig bad;
    bad.eye_separation_m = -1.0;
    const auto path = (temp_dir() / "refused.json").string();
    EXPECT_THROW(save_display_config(path, bad), Error);
    EXPECT_THROW(save_display_config((temp_dir() / "no_dir" / "x.json").string(), DisplayConfig{}), Error);
}

}  // namespace
}  // namespace tridex::renderer
