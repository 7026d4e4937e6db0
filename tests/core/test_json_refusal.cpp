// core/text/json_refusal.hpp: a JSON text's refusal said with its place. nlohmann places a syntax error itself; a number
// beyond a double's range is placed by parsing again (JsonPlaceFinder), naming the line, the column and the field.
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "core/text/json_refusal.hpp"

namespace tridex {
namespace {

using nlohmann::json;

// The refusal of `text`, or "" when it parses.
std::string refusal(const std::string& text) {
    try {
        const json parsed = json::parse(text);
        (void)parsed;
    } catch (const json::exception& e) {
        return json_refusal<json>(text, e);
    }
    return "";
}

TEST(JsonPlace, FollowsObjectsAndArraysToTheRefusedToken) {
    const std::string text = "{\n  \"a\": 1,\n  \"objects\": [ {\"r\": 2}, {\"r\": 3, \"s\": [0, 1e400]} ]\n}\n";
    const JsonPlace p = json_error_place<json>(text);
    EXPECT_EQ(p.line, 3u);
    EXPECT_EQ(p.column, text.substr(text.find("\n  \"objects\"") + 1).find("1e400") + 1);
    EXPECT_EQ(p.field, "objects[1].s[1]");
    EXPECT_EQ(json_error_place<json>("{\"a\": [1, 2]}").line, 0u);  // parses: no place
    EXPECT_EQ(json_error_place<json>("-1e999").field, "");           // the top-level value
}

TEST(JsonPlace, ANumberBeyondADoubleNamesItsLineColumnAndField) {
    EXPECT_EQ(refusal("{ \"workpiece\": {\n    \"resolution\": 64,\n    \"stock_m\": 1e400 } }"),
              "number overflow at line 3, column 16, field 'workpiece.stock_m': '1e400' is beyond a double's range "
              "(magnitudes up to about 1.8e308)");
    EXPECT_EQ(refusal("{\"refresh_hz\": -1e400}"),
              "number overflow at line 1, column 16, field 'refresh_hz': '-1e400' is beyond a double's range "
              "(magnitudes up to about 1.8e308)");
    EXPECT_EQ(refusal("1e400"), "number overflow at line 1, column 1, the top-level value: '1e400' is beyond a "
                                "double's range (magnitudes up to about 1.8e308)");
    // A key that quotes control bytes stays one line.
    EXPECT_EQ(refusal("{\"a\\nb\": 1e400}").find('\n'), std::string::npos);
}

TEST(JsonPlace, ASyntaxErrorKeepsTheParsersOwnPlace) {
    const std::string said = refusal("{\n  \"a\": 1\n  \"b\": 2\n}");
    EXPECT_EQ(said.rfind("parse error at line 3, column ", 0), 0u) << said;
    EXPECT_NE(said.find("syntax error while parsing object"), std::string::npos) << said;
    EXPECT_EQ(said.find("[json.exception"), std::string::npos) << said;
}

}  // namespace
}  // namespace tridex
