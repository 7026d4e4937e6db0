// Encoder quantisation and sensor noise: the simulated device's SensorModel (off by default, quantised positions on
// the grid, seeded noise that repeats, velocity from differences) and the Falcon emulator's encoder noise.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "devices/falcon/falcon_device.hpp"
#include "devices/falcon/falcon_emulator.hpp"
#include "devices/falcon/falcon_firmware.hpp"
#include "devices/simulated_device.hpp"

namespace tridex::devices {
namespace {

ScriptedPath slide() { return ScriptedPath({0.0, 1.0}, {Vec3(0.0), Vec3(0.01, -0.005, 0.002)}); }

std::vector<DeviceState> samples(const SensorModel* sensor, int n) {
    SimulatedDevice d(DeviceProfile::phantom_omni(), slide());
    if (sensor) d.set_sensor(*sensor);
    std::vector<DeviceState> out(static_cast<std::size_t>(n));
    for (DeviceState& s : out) EXPECT_TRUE(d.read(s));
    return out;
}

TEST(SensorModel, OffByDefaultIsExact) {
    SimulatedDevice d(DeviceProfile::phantom_omni(), slide());
    DeviceState s;
    for (int i = 0; i < 100; ++i) {
        ASSERT_TRUE(d.read(s));
        EXPECT_EQ(s.pose.position, d.position_m());
        EXPECT_EQ(s.velocity_m_s, d.velocity_m_s());
    }
}

TEST(SensorModel, QuantisesNoisesAndRepeatsWithTheSeed) {
    SensorModel m;
    m.quantum_m = 0.055e-3;
    m.noise_std_m = 0.02e-3;
    m.seed = 42;
    const std::vector<DeviceState> a = samples(&m, 500), b = samples(&m, 500), exact = samples(nullptr, 500);
    double err2 = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].pose.position, b[i].pose.position) << "the same seed must give the same samples";
        for (int k = 0; k < 3; ++k) {
            const double steps = a[i].pose.position[k] / m.quantum_m;
            EXPECT_NEAR(steps, std::round(steps), 1e-6) << "not on the encoder grid";
            const double e = a[i].pose.position[k] - exact[i].pose.position[k];
            EXPECT_LT(std::abs(e), m.quantum_m / 2 + 5 * m.noise_std_m);
            err2 += e * e;
        }
        if (i > 0) {
            const Vec3 v = (a[i].pose.position - a[i - 1].pose.position) / 1e-3;
            EXPECT_NEAR(glm::length(a[i].velocity_m_s - v), 0.0, 1e-9) << "velocity is not the measured difference";
        }
    }
    // Quantisation (q^2/12) plus noise: the measured error is of that size, not zero.
    const double rms = std::sqrt(err2 / (3.0 * static_cast<double>(a.size())));
    EXPECT_GT(rms, 0.5 * std::sqrt(m.quantum_m * m.quantum_m / 12 + m.noise_std_m * m.noise_std_m));
    m.seed = 43;
    const std::vector<DeviceState> c = samples(&m, 500);
    int differ = 0;
    for (std::size_t i = 0; i < a.size(); ++i) differ += a[i].pose.position != c[i].pose.position;
    EXPECT_GT(differ, 100);
}

TEST(SensorModel, RefusesNegativeValues) {
    SimulatedDevice d(DeviceProfile::phantom_omni(), slide());
    SensorModel m;
    m.quantum_m = -1e-5;
    EXPECT_THROW(d.set_sensor(m), Error);
    m.quantum_m = 0.0;
    m.noise_std_m = std::nan("");
    EXPECT_THROW(d.set_sensor(m), Error);
}

// The Falcon's grip position through the driver, over the emulator with `noise` counts of encoder noise.
std::vector<Vec3> falcon_positions(double noise, std::uint32_t seed) {
    falcon::FalconEmulatorConfig c;
    c.encoder_noise_counts = noise;
    c.noise_seed = seed;
    falcon::FalconDeviceOptions o;
    o.firmware_image = falcon::emulator_firmware_image();
    falcon::FalconDevice dev(std::make_unique<falcon::FalconEmulator>(std::move(c)), o);
    dev.bring_up();
    std::vector<Vec3> out;
    DeviceState s;
    for (int i = 0; i < 200; ++i) {
        EXPECT_TRUE(dev.read(s));
        dev.write(Vec3(0.0), Vec3(0.0));
        out.push_back(s.pose.position);
    }
    return out;
}

TEST(SensorModel, FalconEmulatorEncoderNoise) {
    const std::vector<Vec3> quiet = falcon_positions(0.0, 1), noisy = falcon_positions(3.0, 1),
                            again = falcon_positions(3.0, 1);
    double worst = 0.0;
    int differ = 0;
    for (std::size_t i = 0; i < quiet.size(); ++i) {
        EXPECT_EQ(noisy[i], again[i]);
        worst = std::max(worst, glm::length(noisy[i] - quiet[i]));
        differ += noisy[i] != quiet[i];
    }
    EXPECT_GT(differ, 100);
    EXPECT_LT(worst, 3e-3);  // a few counts of ~64 um each
    falcon::FalconEmulatorConfig bad;
    bad.encoder_noise_counts = -1.0;
    EXPECT_THROW(falcon::FalconEmulator{bad}, Error);
}

}  // namespace
}  // namespace tridex::devices
