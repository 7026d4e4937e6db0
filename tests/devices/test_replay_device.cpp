// Tests of devices/replay_device: it plays exactly the recorded samples in order and then vanishes,
// records what is written without being affected by it, and a closed-loop session recorded to a file
// and replayed through the same controller reproduces every force bit for bit.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <unistd.h>

#include "devices/device_profiles.hpp"
#include "devices/recording.hpp"
#include "devices/replay_device.hpp"
#include "devices/simulated_device.hpp"

namespace tridex::devices {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool same_bits(const Vec3& a, const Vec3& b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z); }
bool same_state(const DeviceState& a, const DeviceState& b) {
    const Quat &p = a.pose.orientation, &q = b.pose.orientation;
    return same_bits(a.t_s, b.t_s) && same_bits(a.pose.position, b.pose.position) && same_bits(p.w, q.w) &&
           same_bits(p.x, q.x) && same_bits(p.y, q.y) && same_bits(p.z, q.z) &&
           same_bits(a.velocity_m_s, b.velocity_m_s) && a.buttons == b.buttons;
}

// n distinct samples; sample 2 carries a NaN position (a flagged sample must replay as recorded).
std::vector<DeviceState> samples(int n) {
    std::vector<DeviceState> out;
    for (int i = 0; i < n; ++i) {
        DeviceState s;
        s.t_s = 1e-3 * (i + 1);
        s.pose.position = Vec3(0.001 * i, -0.002 * i, 0.5 / (i + 1));
        s.pose.orientation = glm::angleAxis(0.01 * i, Vec3(0.0, 1.0, 0.0));
        s.velocity_m_s = Vec3(0.1 * i, 0.0, -0.0);
        s.buttons = static_cast<std::uint32_t>(i & 3);
        if (i == 2) s.pose.position.y = kNaN;
        out.push_back(s);
    }
    return out;
}

TEST(ReplayDevice, PlaysTheRecordedStatesInOrderThenVanishes) {
    const std::vector<DeviceState> src = samples(7);
    ReplayDevice dev(DeviceProfile::phantom_omni(), src);
    dev.bring_up();  // forces pass only while enabled
    EXPECT_EQ(dev.profile().name, "PHANTOM Omni");
    DeviceState s;
    for (std::size_t i = 0; i < src.size(); ++i) {
        EXPECT_EQ(dev.played(), i);
        ASSERT_TRUE(dev.read(s));
        EXPECT_TRUE(same_state(s, src[i])) << "sample " << i;
        EXPECT_FALSE(dev.finished());
    }
    EXPECT_EQ(dev.played(), src.size());
    // The device is gone after the last sample, and stays gone; `out` is left alone.
    const DeviceState last = s;
    EXPECT_FALSE(dev.read(s));
    EXPECT_TRUE(dev.finished());
    EXPECT_FALSE(dev.read(s));
    EXPECT_EQ(dev.played(), src.size());
    EXPECT_TRUE(same_state(s, last));
}

TEST(ReplayDevice, EmptyReplayVanishesAtOnce) {
    ReplayDevice dev(DeviceProfile::phantom_omni(), {});
    dev.bring_up();  // forces pass only while enabled
    DeviceState s;
    EXPECT_FALSE(dev.read(s));
    EXPECT_TRUE(dev.finished());
    EXPECT_EQ(dev.played(), 0u);
    dev.write(Vec3(0.0), Vec3(0.0));  // the loop's final zero force is still stored
    ASSERT_EQ(dev.forces_written().size(), 1u);
}

TEST(ReplayDevice, WritesAreRecordedAndNeverChangeThePlayback) {
    const std::vector<DeviceState> src = samples(5);
    ReplayDevice dev(generic_6dof(), src);  // 3 N, 0.3 N*m
    dev.bring_up();  // forces pass only while enabled
    DeviceState s;
    std::vector<Vec3> forces, torques;
    for (std::size_t i = 0; i < src.size(); ++i) {
        ASSERT_TRUE(dev.read(s));
        EXPECT_TRUE(same_state(s, src[i]));
        // A force would move a real (or simulated) device; a replay ignores it.
        const Vec3 f(0.5 * (i + 1), -1.0, i == 3 ? kNaN : 0.25);
        const Vec3 t(0.0, 0.01 * i, 0.0);
        dev.write(f, t);
        // What reaches the driver: the device seam sends a non-finite force (and its torque) as zero.
        forces.push_back(i == 3 ? Vec3(0.0) : f);
        torques.push_back(i == 3 ? Vec3(0.0) : t);
    }
    ASSERT_EQ(dev.forces_written().size(), src.size());
    ASSERT_EQ(dev.torques_written().size(), src.size());
    for (std::size_t i = 0; i < src.size(); ++i) {
        EXPECT_TRUE(same_bits(dev.forces_written()[i], forces[i])) << i;  // stored as the driver got them
        EXPECT_TRUE(same_bits(dev.torques_written()[i], torques[i])) << i;
    }
    // Beyond samples + kExtraWrites writes are counted but not stored (no allocation in the loop).
    const std::size_t extra = ReplayDevice::kExtraWrites + 4;
    const auto* before = dev.forces_written().data();
    for (std::size_t k = 0; k < extra; ++k) dev.write(Vec3(0.0), Vec3(0.0));
    EXPECT_EQ(dev.writes(), src.size() + extra);
    EXPECT_EQ(dev.forces_written().size(), src.size() + ReplayDevice::kExtraWrites);
    EXPECT_EQ(dev.torques_written().size(), src.size() + ReplayDevice::kExtraWrites);
    EXPECT_EQ(dev.forces_written().data(), before);  // never reallocated
}

// A deterministic controller standing in for the haptic loop: a virtual wall z >= 0 with stiffness k
// and damping b (F = k*d - b*v_z inside, zero outside); zero force on a non-finite sample.
Vec3 wall_force(const DeviceState& s) {
    if (!is_finite(s.pose.position) || !is_finite(s.velocity_m_s) || !std::isfinite(s.t_s)) return Vec3(0.0);
    const double depth = -s.pose.position.z;
    if (depth <= 0.0) return Vec3(0.0);
    return Vec3(0.0, 0.0, 500.0 * depth - 1.0 * s.velocity_m_s.z);
}

TEST(ReplayDevice, RecordedClosedLoopSessionReplaysIdentically) {
    // Live: the simulated hand pushes 5 mm into the wall and back; the wall force acts on the device.
    const ScriptedPath path({0.0, 0.2, 0.4, 0.6}, {Vec3(0.0, 0.0, 0.01), Vec3(0.0, 0.0, -0.005),
                                                   Vec3(0.002, 0.0, -0.005), Vec3(0.0, 0.0, 0.01)});
    SimulatedDevice live(DeviceProfile::phantom_omni(), path);
    live.bring_up();  // forces pass only while enabled
    SimulatedFaults faults;
    faults.nan_first_read = 300;  // 3 samples with a NaN position, while in contact
    faults.nan_count = 3;
    faults.vanish_after_reads = 700;
    live.set_faults(faults);

    Recording rec;
    rec.header.device_name = live.profile().name;
    rec.header.period_s = 1e-3;
    rec.header.workspace_mode = "scaling";
    std::vector<Vec3> live_forces;
    DeviceState s;
    std::size_t contact_ticks = 0;
    while (live.read(s)) {
        const Vec3 f = wall_force(s);
        live.write(f, Vec3(0.0));
        live_forces.push_back(live.last_force_n());  // what the device got (bounded by its 0.88 N)
        RecordedTick t;
        t.t_s = s.t_s;
        t.device = s;
        t.valid = is_finite(s.pose.position) ? 1 : 0;
        t.wand_centre_m = t.valid ? s.pose.position : rec.ticks.back().wand_centre_m;
        t.top_m = t.bottom_m = t.top_contact_m = t.bottom_contact_m = t.wand_centre_m;
        t.top_deviation_m = t.valid ? std::max(0.0, -s.pose.position.z) : 0.0;
        t.top_force_n = t.force_n = f;
        t.top_collision_id = t.top_deviation_m > 0.0 ? 0 : -1;
        t.buttons = s.buttons;
        contact_ticks += t.top_collision_id == 0;
        rec.ticks.push_back(t);
    }
    ASSERT_EQ(rec.ticks.size(), 700u);
    ASSERT_GT(contact_ticks, 100u);  // the session really pushed into the wall

    const std::string file = (std::filesystem::temp_directory_path() /
                              ("tridex_replay_" + std::to_string(::getpid()) + ".trdxrec")).string();
    write_recording(file, rec);
    const Recording back = read_recording(file);
    std::filesystem::remove(file);

    // Replay: same controller, device samples from the file, until the device vanishes.
    ReplayDevice replay(DeviceProfile::phantom_omni(), device_states(back));
    replay.bring_up();  // forces pass only while enabled
    ASSERT_EQ(replay.samples().size(), 700u);
    std::size_t ticks = 0;
    while (replay.read(s)) {
        EXPECT_TRUE(same_state(s, rec.ticks[ticks].device)) << "tick " << ticks;
        replay.write(wall_force(s), Vec3(0.0));
        ++ticks;
    }
    EXPECT_EQ(ticks, 700u);
    EXPECT_EQ(replay.played(), 700u);
    ASSERT_EQ(replay.forces_written().size(), live_forces.size());
    std::size_t identical = 0;
    double max_force = 0.0;
    for (std::size_t i = 0; i < live_forces.size(); ++i) {
        identical += same_bits(replay.forces_written()[i], live_forces[i]);
        max_force = std::max(max_force, glm::length(live_forces[i]));
    }
    EXPECT_EQ(identical, live_forces.size());
    // Reads 300..302 (indices 299..301) had a NaN position and sent zero force, in contact on both sides.
    for (std::size_t i = 299; i <= 301; ++i) EXPECT_EQ(replay.forces_written()[i], Vec3(0.0)) << i;
    EXPECT_GT(replay.forces_written()[298].z, 0.0);
    EXPECT_GT(replay.forces_written()[302].z, 0.0);
    std::printf("replayed %zu ticks (%zu in contact, peak wall force %.4f N): %zu of %zu forces bit-identical\n", ticks,
                contact_ticks, max_force, identical, live_forces.size());
}

}  // namespace
}  // namespace tridex::devices
