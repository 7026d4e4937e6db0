// Clay ops through the session spec: "push", "smooth", "pull" and "grab" parse, round-trip through the recording
// header, reach the haptic loop without the cutting force (the god-object holds the tool on the reference surface),
// and unknown names list them.
#include <gtest/gtest.h>

#include <string>

#include "app/scene/session_spec.hpp"
#include "core/error.hpp"
#include "core/tool_sample.hpp"

namespace tridex::app {
namespace {

TEST(ClaySpec, PushAndSmoothReachTheLoopWithoutTheCuttingForce) {
    for (const char* name : {"push", "smooth", "pull", "grab"}) {
        SessionSpec s;
        s.op = name;
        const SessionSpec back = spec_from_json(spec_to_json(s), "test");
        EXPECT_EQ(back.op, name);
        const haptics::HapticLoopConfig cfg = loop_config(back, 10);
        EXPECT_EQ(cfg.op, parse_tool_op(name));
        EXPECT_STREQ(tool_op_name(cfg.op), name);
        EXPECT_FALSE(cfg.contact.cutting);
    }
    EXPECT_EQ(parse_tool_op("push"), ToolOp::kPush);
    EXPECT_EQ(parse_tool_op("smooth"), ToolOp::kSmooth);
    EXPECT_EQ(parse_tool_op("pull"), ToolOp::kPull);
    EXPECT_EQ(parse_tool_op("grab"), ToolOp::kGrab);
    try {
        parse_tool_op("mould");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("push, smooth, pull, grab"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace tridex::app
