// A recording streamed while the session runs (app/session/record/tick_stream.hpp): longer than any in-memory record
// buffer, bounded memory, written atomically, nothing left in the folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <thread>

#include "app/session/record/tick_stream.hpp"
#include "devices/recording.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

haptics::TickRecord tick_at(std::size_t i) {
    haptics::TickRecord r;
    r.t_s = 1e-3 * static_cast<double>(i);
    r.hip_m = Vec3(1e-6 * static_cast<double>(i % 1000), 0.0, 0.3);
    r.tool_world.position = r.hip_m;
    r.device.pose.position = r.hip_m;
    r.device.t_s = r.t_s;
    r.op = ToolOp::kSubtract;
    r.material = 1;
    r.tool = ToolShape{ToolKind::kBall, 0.008, 0.0, 0};
    return r;
}

// 200,000 ticks (over three minutes at 1 kHz, past the 120,000 records a live session keeps in memory) pushed by a
// producer as the haptic loop pushes them, drained by the stream's thread: the recording holds every one, in order.
TEST(TickStream, ARecordingHasNoLengthLimit) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_tick_stream";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string path = (dir / "long.trdx").string();
    SessionSpec spec;
    constexpr std::size_t kTicks = 200000;
    {
        TickStream stream(spec, path);
        stream.start();
        std::size_t waits = 0;
        for (std::size_t i = 0; i < kTicks; ++i) {
            while (!stream.ring().try_push(tick_at(i))) {  // the loop would drop it; this producer waits
                ++waits;
                std::this_thread::yield();
            }
        }
        stream.stop();
        EXPECT_EQ(stream.ticks(), kTicks);
        EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0)
            << "the streamed ticks showed in the folder before the recording was written";
        stream.finish("", {});
    }
    const devices::Recording rec = devices::read_recording(path);
    ASSERT_EQ(rec.ticks.size(), kTicks);
    EXPECT_DOUBLE_EQ(rec.ticks.front().t_s, 0.0);
    EXPECT_DOUBLE_EQ(rec.ticks.back().t_s, 1e-3 * static_cast<double>(kTicks - 1));
    EXPECT_DOUBLE_EQ(rec.ticks[12345].wand_centre_m.x, 1e-6 * 345.0);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "a temporary file was left";
    fs::remove_all(dir);
}

// A stream that is never finished (the session failed) leaves nothing: no recording, no temporary file.
TEST(TickStream, AnUnfinishedStreamLeavesNothing) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_tick_stream_unfinished";
    fs::remove_all(dir);
    fs::create_directories(dir);
    {
        TickStream stream(SessionSpec{}, (dir / "lost.trdx").string());
        stream.start();
        for (std::size_t i = 0; i < 1000; ++i) ASSERT_TRUE(stream.ring().try_push(tick_at(i)));
    }
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace tridex::app
