// Tests of devices/recording: bit-identical round trip, the documented layout and size, every refusal
// (missing, truncated, wrong magic/version/size, unfinished, trailing bytes, NaN, time going back,
// corrupted bytes, bad header), the writer's checks, the CSV export, CRC-32 and axis-angle.
// It is over 600 lines because every refusal of the recording reader is one case of one table-like suite, and
// splitting the suite would scatter the format's refusals over files.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "devices/recording.hpp"

namespace tridex::devices {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// This process's scratch directory (removed when the tests end).
fs::path temp_dir() { return fs::temp_directory_path() / ("tridex_rec_" + std::to_string(::getpid())); }

class TempDirCleanup : public ::testing::Environment {
public:
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(temp_dir(), ec);
    }
};
[[maybe_unused]] ::testing::Environment* const kCleanup = ::testing::AddGlobalTestEnvironment(new TempDirCleanup);

// A fresh path in the scratch directory, unique per test and process.
std::string temp_path(const std::string& name) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    fs::create_directories(temp_dir());
    return (temp_dir() / (std::string(info->name()) + "_" + name)).string();
}

std::vector<unsigned char> load(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(in), {});
}
void save(const std::string& path, const std::vector<unsigned char>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}
void put_f64(std::vector<unsigned char>& b, std::size_t at, double v) {
    const auto u = std::bit_cast<std::uint64_t>(v);
    for (int i = 0; i < 8; ++i) b[at + i] = static_cast<unsigned char>(u >> (8 * i));
}
std::uint32_t get_u32(const std::vector<unsigned char>& b, std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(b[at + i]) << (8 * i);
    return v;
}

// A deterministic, varied session of n ticks: every field differs per tick, awkward doubles included
// (-0.0, subnormal, 1/3), one invalid sample with NaN/inf in its device fields.
Recording sample_recording(int n) {
    Recording r;
    r.header.device_name = "PHANTOM Omni";
    r.header.period_s = 1e-3 / 3.0;
    r.header.workspace_mode = "moving";
    r.header.notes = "{\"mesh\": \"bunny.obj\", \"n\": 256}\nline two \xC3\xA9\t\"quoted\"";
    for (int i = 0; i < n; ++i) {
        const double s = i + 1.0;
        RecordedTick t;
        t.t_s = 0.001 * s + 1.0 / 3.0;
        t.device.t_s = t.t_s - 1e-7;
        t.device.pose.position = Vec3(0.01 * s, -0.02 / s, 1e-3 * std::sin(s));
        t.device.pose.orientation = glm::angleAxis(0.1 * s, glm::normalize(Vec3(1.0, s, -2.0)));
        t.device.velocity_m_s = Vec3(-0.0, 4.9e-324 * s, 0.3 * s);
        t.device.buttons = static_cast<std::uint32_t>(i % 4);
        t.wand_centre_m = Vec3(1.0 + s, 2.0 - s, 3.0 / s);
        to_axis_angle(t.device.pose.orientation, t.rotation_axis, t.rotation_angle_rad);
        t.top_m = t.wand_centre_m + Vec3(0.0, 0.0, 0.05);
        t.bottom_m = t.wand_centre_m - Vec3(0.0, 0.0, 0.05);
        t.top_contact_m = t.top_m + Vec3(1e-4 * s, 0.0, 0.0);
        t.bottom_contact_m = t.bottom_m - Vec3(0.0, 2e-4 * s, 0.0);
        t.top_deviation_m = 1e-4 * s;
        t.bottom_deviation_m = i % 3 == 0 ? 0.0 : 2e-4 * s;
        t.top_force_n = Vec3(0.1 * s, -0.2, 1.0 / 3.0);
        t.bottom_force_n = Vec3(-0.05, 0.07 * s, -0.0);
        t.force_n = t.top_force_n + t.bottom_force_n;
        t.torque_nm = Vec3(-0.02 * s, 0.01, 1e-300);
        t.top_collision_id = i % 5 == 0 ? -1 : 1000 * i;
        t.bottom_collision_id = i % 7 == 0 ? -1 : 2147483647 - i;
        t.buttons = 0x80000000u | static_cast<std::uint32_t>(i);
        t.tool_mode = static_cast<std::uint8_t>(i % 8);  // every ToolOp value, kGrab (7) included
        t.op = static_cast<std::uint8_t>((i + 1) % 8);
        t.material = static_cast<std::uint8_t>(i % 8);
        t.tool.kind = i % 3 == 0 ? ToolKind::kFlatEnd : ToolKind::kBall;
        t.tool.radius_m = 0.006 * std::pow(1.25, i % 5);
        t.tool.length_m = t.tool.kind == ToolKind::kFlatEnd ? 0.02 / 3.0 : 0.0;
        if (i % 3 == 1) t.symmetry.mirrors = static_cast<std::uint8_t>(1 + i % 7);
        if (i % 3 == 2) t.symmetry = Symmetry{0, static_cast<std::uint8_t>(i % 3), static_cast<std::uint16_t>(2 + i % 31)};
        t.workpiece = i % kMaxRecordedWorkpieces;  // every workpiece index
        t.valid = 1;
        if (i == n / 2) {  // a sample the loop flagged: the device gave NaN and infinity
            t.valid = 0;
            t.device.pose.position = Vec3(kNaN, 0.0, std::numeric_limits<double>::infinity());
            t.device.t_s = kNaN;
        }
        r.ticks.push_back(t);
    }
    return r;
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
bool same_bits(const Vec3& a, const Vec3& b) { return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z); }

void expect_identical(const RecordedTick& a, const RecordedTick& b, std::size_t i) {
    SCOPED_TRACE("tick " + std::to_string(i));
    EXPECT_TRUE(same_bits(a.t_s, b.t_s));
    EXPECT_TRUE(same_bits(a.device.t_s, b.device.t_s));
    EXPECT_TRUE(same_bits(a.device.pose.position, b.device.pose.position));
    EXPECT_TRUE(same_bits(a.device.pose.orientation.w, b.device.pose.orientation.w));
    EXPECT_TRUE(same_bits(a.device.pose.orientation.x, b.device.pose.orientation.x));
    EXPECT_TRUE(same_bits(a.device.pose.orientation.y, b.device.pose.orientation.y));
    EXPECT_TRUE(same_bits(a.device.pose.orientation.z, b.device.pose.orientation.z));
    EXPECT_TRUE(same_bits(a.device.velocity_m_s, b.device.velocity_m_s));
    EXPECT_EQ(a.device.buttons, b.device.buttons);
    EXPECT_TRUE(same_bits(a.wand_centre_m, b.wand_centre_m));
    EXPECT_TRUE(same_bits(a.rotation_axis, b.rotation_axis));
    EXPECT_TRUE(same_bits(a.rotation_angle_rad, b.rotation_angle_rad));
    EXPECT_TRUE(same_bits(a.top_m, b.top_m));
    EXPECT_TRUE(same_bits(a.bottom_m, b.bottom_m));
    EXPECT_TRUE(same_bits(a.top_contact_m, b.top_contact_m));
    EXPECT_TRUE(same_bits(a.bottom_contact_m, b.bottom_contact_m));
    EXPECT_TRUE(same_bits(a.top_deviation_m, b.top_deviation_m));
    EXPECT_TRUE(same_bits(a.bottom_deviation_m, b.bottom_deviation_m));
    EXPECT_TRUE(same_bits(a.top_force_n, b.top_force_n));
    EXPECT_TRUE(same_bits(a.bottom_force_n, b.bottom_force_n));
    EXPECT_TRUE(same_bits(a.force_n, b.force_n));
    EXPECT_TRUE(same_bits(a.torque_nm, b.torque_nm));
    EXPECT_EQ(a.top_collision_id, b.top_collision_id);
    EXPECT_EQ(a.bottom_collision_id, b.bottom_collision_id);
    EXPECT_EQ(a.buttons, b.buttons);
    EXPECT_EQ(a.tool_mode, b.tool_mode);
    EXPECT_EQ(a.valid, b.valid);
    EXPECT_EQ(a.op, b.op);
    EXPECT_EQ(a.material, b.material);
    EXPECT_EQ(a.tool.kind, b.tool.kind);
    EXPECT_TRUE(same_bits(a.tool.radius_m, b.tool.radius_m));
    EXPECT_TRUE(same_bits(a.tool.length_m, b.tool.length_m));
    EXPECT_EQ(a.symmetry, b.symmetry);
    EXPECT_EQ(a.workpiece, b.workpiece);
}

// Runs read_recording(path), expects a tridex::Error whose message starts with the path and holds
// every one of `parts`.
void expect_refused(const std::string& path, const std::vector<std::string>& parts) {
    try {
        read_recording(path);
        ADD_FAILURE() << path << " was accepted";
    } catch (const Error& e) {
        const std::string msg = e.what();
        std::printf("refused: %s\n", msg.c_str());
        EXPECT_EQ(msg.rfind(path + ": ", 0), 0u) << msg;
        for (const std::string& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "message is not one line: " << msg;
    }
}

// The written file of sample_recording(n) and where its ticks start.
struct Written {
    std::string path;
    std::vector<unsigned char> bytes;
    std::size_t ticks_at = 0;
};
Written write_sample(const std::string& name, int n) {
    Written w;
    w.path = temp_path(name);
    write_recording(w.path, sample_recording(n));
    w.bytes = load(w.path);
    w.ticks_at = kRecordingPreambleBytes + get_u32(w.bytes, 28);
    return w;
}

// `w`'s preamble with no ticks and header text `text` (its length and CRC set), written as `name`; returns its path.
std::string file_with_header(const Written& w, const std::string& name, const std::string& text) {
    std::vector<unsigned char> b(w.bytes.begin(), w.bytes.begin() + 32);
    b[28] = static_cast<unsigned char>(text.size()), b[29] = b[30] = b[31] = 0;
    b[16] = 0;  // zero ticks
    b.insert(b.end(), text.begin(), text.end());
    const std::uint32_t crc = crc32_ieee(text.data(), text.size());
    for (int i = 0; i < 4; ++i) b[24 + i] = static_cast<unsigned char>(crc >> (8 * i));
    const std::string p = temp_path(name);
    save(p, b);
    return p;
}

TEST(Crc32, KnownCheckValue) {
    // The standard check value of CRC-32/IEEE (zlib, PNG) for the ASCII digits 1..9.
    EXPECT_EQ(crc32_ieee("123456789", 9), 0xCBF43926u);
    // Continuing a CRC over two parts equals one pass over the whole.
    EXPECT_EQ(crc32_ieee("6789", 4, crc32_ieee("12345", 5)), 0xCBF43926u);
    EXPECT_EQ(crc32_ieee("", 0), 0u);
}

TEST(AxisAngle, MatchesTheRotation) {
    const Vec3 axis = glm::normalize(Vec3(1.0, 2.0, -3.0));
    for (double angle : {1e-6, 0.7, 3.0, 3.5, 6.0}) {
        SCOPED_TRACE(angle);
        Vec3 a;
        double th = 0.0;
        to_axis_angle(glm::angleAxis(angle, axis), a, th);
        // Angles above pi come back as 2*pi - angle about the opposite axis (the same rotation).
        const double expect = angle <= glm::pi<double>() ? angle : 2.0 * glm::pi<double>() - angle;
        const Vec3 expect_axis = angle <= glm::pi<double>() ? axis : -axis;
        EXPECT_NEAR(th, expect, 1e-12);
        EXPECT_NEAR(glm::length(a - expect_axis), 0.0, 1e-9);
        EXPECT_NEAR(glm::length(a), 1.0, 1e-15);
        // The negated quaternion is the same rotation.
        to_axis_angle(-glm::angleAxis(angle, axis), a, th);
        EXPECT_NEAR(th, expect, 1e-12);
    }
    Vec3 a;
    double th = -1.0;
    to_axis_angle(Quat(2.0, 0.0, 0.0, 0.0), a, th);  // identity, not normalised
    EXPECT_EQ(th, 0.0);
    EXPECT_EQ(a, Vec3(1.0, 0.0, 0.0));
    to_axis_angle(Quat(0.0, 0.0, 0.0, 0.0), a, th);
    EXPECT_TRUE(std::isnan(th));
    to_axis_angle(Quat(kNaN, 0.0, 0.0, 0.0), a, th);
    EXPECT_TRUE(std::isnan(th));
}

TEST(Recording, RoundTripIsBitIdentical) {
    const Recording src = sample_recording(2500);  // more than two read chunks of 1024 ticks
    const std::string path = temp_path("a.trdxrec");
    write_recording(path, src);
    const Recording back = read_recording(path);
    EXPECT_EQ(back.header.device_name, src.header.device_name);
    EXPECT_TRUE(same_bits(back.header.period_s, src.header.period_s));
    EXPECT_EQ(back.header.workspace_mode, src.header.workspace_mode);
    EXPECT_EQ(back.header.notes, src.header.notes);
    ASSERT_EQ(back.ticks.size(), src.ticks.size());
    for (std::size_t i = 0; i < src.ticks.size(); ++i) expect_identical(src.ticks[i], back.ticks[i], i);
    // Only the flagged tick holds non-finite values, and only in its device sample.
    std::size_t nan_ticks = 0;
    for (const RecordedTick& t : back.ticks) {
        EXPECT_TRUE(check_tick(t, kNaN).empty());
        if (!is_finite(t.device.pose.position)) {
            ++nan_ticks;
            EXPECT_EQ(t.valid, 0);
        }
        EXPECT_TRUE(is_finite(t.force_n) && is_finite(t.wand_centre_m) && std::isfinite(t.top_deviation_m));
    }
    EXPECT_EQ(nan_ticks, 1u);
}

TEST(Recording, LayoutAndBytesPerTick) {
    const int n = 10;
    const Written w = write_sample("a.trdxrec", n);
    const std::size_t header_len = get_u32(w.bytes, 28);
    EXPECT_EQ(w.bytes.size(), kRecordingPreambleBytes + header_len + n * kRecordedTickBytes);
    EXPECT_EQ(std::memcmp(w.bytes.data(), "TRDXREC\0", 8), 0);
    EXPECT_EQ(get_u32(w.bytes, 8), 4u);
    EXPECT_EQ(get_u32(w.bytes, 12), 402u);
    EXPECT_EQ(get_u32(w.bytes, 16), static_cast<std::uint32_t>(n));
    EXPECT_EQ(get_u32(w.bytes, 20), 0u);  // high half of the u64 tick count
    // The checksum covers the header text and the ticks.
    EXPECT_EQ(get_u32(w.bytes, 24), crc32_ieee(w.bytes.data() + 32, w.bytes.size() - 32));
    // The header text is the documented JSON object.
    const std::string text(w.bytes.begin() + 32, w.bytes.begin() + 32 + static_cast<long>(header_len));
    EXPECT_NE(text.find("\"device_name\":\"PHANTOM Omni\""), std::string::npos) << text;
    // Documented offsets: tick 0's t_s at 0 and its valid byte at 377; the force x of tick 1 at 316.
    const Recording src = sample_recording(n);
    std::uint64_t u = 0;
    std::memcpy(&u, w.bytes.data() + w.ticks_at, 8);  // the test host is little-endian (x86-64)
    EXPECT_EQ(std::bit_cast<double>(u), src.ticks[0].t_s);
    EXPECT_EQ(w.bytes[w.ticks_at + 377], 1);
    EXPECT_EQ(w.bytes[w.ticks_at + 376], src.ticks[0].tool_mode);
    // Version 2's fields: op at 378, material at 379, tool kind at 380, radius at 381, length at 389.
    EXPECT_EQ(w.bytes[w.ticks_at + 378], src.ticks[0].op);
    EXPECT_EQ(w.bytes[w.ticks_at + 379], src.ticks[0].material);
    EXPECT_EQ(w.bytes[w.ticks_at + 380], static_cast<unsigned char>(src.ticks[0].tool.kind));
    std::memcpy(&u, w.bytes.data() + w.ticks_at + 381, 8);
    EXPECT_EQ(std::bit_cast<double>(u), src.ticks[0].tool.radius_m);
    std::memcpy(&u, w.bytes.data() + w.ticks_at + 389, 8);
    EXPECT_EQ(std::bit_cast<double>(u), src.ticks[0].tool.length_m);
    std::memcpy(&u, w.bytes.data() + w.ticks_at + kRecordedTickBytes + 316, 8);
    EXPECT_EQ(std::bit_cast<double>(u), src.ticks[1].force_n.x);
    // Version 4's field: the workpiece at 401 (tick 3 carved workpiece 3).
    EXPECT_EQ(w.bytes[w.ticks_at + 3 * kRecordedTickBytes + 401], 3);
    // At 1 kHz: bytes per tick * 1000 ticks/s = that many kB/s (1 kB = 1000 bytes).
    std::printf("bytes per tick: %zu (%zu kB/s at 1 kHz, %.1f MB per minute), header text %zu bytes\n",
                kRecordedTickBytes, kRecordedTickBytes, kRecordedTickBytes * 60e3 / 1e6, header_len);
}

TEST(Recording, EmptySessionRoundTrips) {
    const std::string path = temp_path("empty.trdxrec");
    write_recording(path, Recording{});
    const Recording back = read_recording(path);
    EXPECT_TRUE(back.ticks.empty());
    EXPECT_EQ(back.header.period_s, 1e-3);
}

TEST(Recording, MissingFileRefused) {
    const std::string path = temp_path("does_not_exist.trdxrec");
    expect_refused(path, {"cannot open"});
}

TEST(Recording, TruncatedFilesRefused) {
    const Written w = write_sample("full.trdxrec", 5);
    const std::size_t cuts[] = {0, 5, 20, 31, 40, w.ticks_at - 1, w.ticks_at + 10, w.bytes.size() - kRecordedTickBytes,
                                w.bytes.size() - 1};
    for (std::size_t cut : cuts) {
        SCOPED_TRACE(cut);
        const std::string path = temp_path("cut" + std::to_string(cut) + ".trdxrec");
        save(path, std::vector<unsigned char>(w.bytes.begin(), w.bytes.begin() + static_cast<long>(cut)));
        expect_refused(path, {"truncated"});
    }
    // The message names the tick that is cut.
    const std::string path = temp_path("cut_last.trdxrec");
    save(path, std::vector<unsigned char>(w.bytes.begin(), w.bytes.end() - 1));
    expect_refused(path, {"truncated", "tick 4 is cut at byte " + std::to_string(w.bytes.size() - 1)});
}

TEST(Recording, WrongMagicVersionSizeRefused) {
    const Written w = write_sample("good.trdxrec", 3);
    auto variant = [&](const std::string& name, std::size_t at, unsigned char value) {
        std::vector<unsigned char> b = w.bytes;
        b[at] = value;
        const std::string path = temp_path(name);
        save(path, b);
        return path;
    };
    expect_refused(variant("magic.trdxrec", 3, 'Y'), {"not a tridex recording", "magic"});
    expect_refused(variant("version.trdxrec", 8, 5), {"byte 8", "unsupported version 5", "reads versions 1 to 4"});
    expect_refused(variant("size.trdxrec", 12, 0x7B), {"byte 12", "tick record size 379", "expected 402"});
    // A version 1 preamble over version 4 ticks: the tick size is wrong for version 1.
    expect_refused(variant("v1size.trdxrec", 8, 1), {"byte 12", "tick record size 402", "expected 378 for version 1"});
    // A text file is not a recording.
    const std::string text = temp_path("text.csv");
    std::ofstream(text) << "t_s,force_n\n0.001,0.5\n0.002,0.6\n";
    expect_refused(text, {"not a tridex recording"});
}

// Version 1 files (378-byte ticks ending at `valid`) are still read: op = tool_mode, no tool recorded.
// The `n`-tick sample `w` as a file of an older `version`: each tick cut to that version's `tick_bytes`, the preamble's
// version, tick size and checksum made to match. Returns the file's path.
std::string older_version(const Written& w, int n, std::uint32_t version, std::size_t tick_bytes, const std::string& name) {
    std::vector<unsigned char> b(w.bytes.begin(), w.bytes.begin() + static_cast<long>(w.ticks_at));
    for (int i = 0; i < n; ++i) {
        const auto at = w.bytes.begin() + static_cast<long>(w.ticks_at + i * kRecordedTickBytes);
        b.insert(b.end(), at, at + static_cast<long>(tick_bytes));
    }
    const auto put_u32 = [&b](std::size_t at, std::uint32_t v) {
        for (int k = 0; k < 4; ++k) b[at + k] = static_cast<unsigned char>(v >> (8 * k));
    };
    put_u32(8, version);
    put_u32(12, static_cast<std::uint32_t>(tick_bytes));
    put_u32(24, crc32_ieee(b.data() + 32, b.size() - 32));
    const std::string path = temp_path(name);
    save(path, b);
    return path;
}

// Files of versions 1 to 3 are still read; each version's later fields read as not recorded: version 1 (378-byte
// ticks ending at `valid`) has the op as tool_mode, no material, tool or symmetry; version 2 (397 bytes, ending at the
// tool length) no symmetry; version 3 (401 bytes, ending at the symmetry) no workpiece.
TEST(Recording, OlderVersionsStillRead) {
    const int n = 7;
    const Written w = write_sample("v4.trdxrec", n);
    const Recording src = sample_recording(n);
    const std::size_t sizes[] = {kRecordedTickBytesV1, kRecordedTickBytesV2, kRecordedTickBytesV3};
    for (std::uint32_t version = 1; version <= 3; ++version) {
        SCOPED_TRACE("version " + std::to_string(version));
        const Recording back = read_recording(
            older_version(w, n, version, sizes[version - 1], "v" + std::to_string(version) + ".trdxrec"));
        ASSERT_EQ(back.ticks.size(), src.ticks.size());
        for (std::size_t i = 0; i < src.ticks.size(); ++i) {
            RecordedTick expect = src.ticks[i];
            expect.workpiece = -1;
            if (version < 3) expect.symmetry = Symmetry{};
            if (version < 2) {
                expect.op = expect.tool_mode;
                expect.material = 0;
                expect.tool = ToolShape{};
            }
            expect_identical(expect, back.ticks[i], i);
        }
    }
}

TEST(Recording, TrailingBytesRefused) {
    const Written w = write_sample("good.trdxrec", 3);
    std::vector<unsigned char> b = w.bytes;
    b.push_back(0);
    const std::string path = temp_path("trailing.trdxrec");
    save(path, b);
    expect_refused(path, {"1 trailing byte(s) after tick 3", "byte " + std::to_string(w.bytes.size())});
}

TEST(Recording, CorruptedValuesRefusedNamingTickAndField) {
    const Written w = write_sample("good.trdxrec", 8);
    const Recording src = sample_recording(8);
    auto patched = [&](const std::string& name, std::size_t tick, std::size_t offset, double value) {
        std::vector<unsigned char> b = w.bytes;
        put_f64(b, w.ticks_at + tick * kRecordedTickBytes + offset, value);
        const std::string path = temp_path(name);
        save(path, b);
        return path;
    };
    const std::string tick3 = "tick 3 (byte " + std::to_string(w.ticks_at + 3 * kRecordedTickBytes) + ")";
    expect_refused(patched("dev.trdxrec", 3, 252, kNaN), {tick3, "top_deviation_m = nan"});
    expect_refused(patched("force.trdxrec", 3, 316 + 16, std::numeric_limits<double>::infinity()),
                   {tick3, "force_n", "not finite"});
    expect_refused(patched("negdev.trdxrec", 3, 260, -1e-3), {tick3, "bottom_deviation_m = -0.001"});
    expect_refused(patched("axis.trdxrec", 3, 124, 2.0), {tick3, "rotation_axis", "not unit length"});
    // Tick 3 valid = 1 but its device position is NaN.
    expect_refused(patched("devpos.trdxrec", 3, 16, kNaN), {tick3, "device.pose.position"});
    // Time: tick 3 at the time of tick 2 (equal is not increasing), and going back.
    expect_refused(patched("same_t.trdxrec", 3, 0, src.ticks[2].t_s), {tick3, "does not increase"});
    expect_refused(patched("back_t.trdxrec", 3, 0, src.ticks[1].t_s), {tick3, "does not increase"});
    expect_refused(patched("nan_t.trdxrec", 3, 0, kNaN), {tick3, "t_s = nan is not finite"});
    expect_refused(patched("radius.trdxrec", 3, 381, -0.004), {tick3, "tool.radius_m = -0.004"});
    expect_refused(patched("length.trdxrec", 3, 389, kNaN), {tick3, "tool.length_m = nan"});
    // Flag bytes out of range.
    std::vector<unsigned char> b = w.bytes;
    b[w.ticks_at + 3 * kRecordedTickBytes + 377] = 2;
    std::string path = temp_path("valid.trdxrec");
    save(path, b);
    expect_refused(path, {tick3, "valid = 2"});
    b = w.bytes;
    b[w.ticks_at + 3 * kRecordedTickBytes + 376] = 9;  // one past kPlace
    path = temp_path("mode.trdxrec");
    save(path, b);
    expect_refused(path, {tick3, "tool_mode = 9"});
    // An id below -1.
    b = w.bytes;
    b[w.ticks_at + 3 * kRecordedTickBytes + 364] = 0xFE;
    for (int k = 1; k < 4; ++k) b[w.ticks_at + 3 * kRecordedTickBytes + 364 + k] = 0xFF;
    path = temp_path("id.trdxrec");
    save(path, b);
    expect_refused(path, {tick3, "top_collision_id = -2"});
    // A workpiece index past the most a loop has.
    b = w.bytes;
    b[w.ticks_at + 3 * kRecordedTickBytes + 401] = 8;
    path = temp_path("workpiece.trdxrec");
    save(path, b);
    expect_refused(path, {tick3, "workpiece = 8", "is not a workpiece index (0..7)"});
}

TEST(Recording, FlippedBitCaughtByChecksum) {
    const Written w = write_sample("good.trdxrec", 8);
    // A one-bit change that leaves every value plausible: the lowest mantissa bit of a force.
    std::vector<unsigned char> b = w.bytes;
    b[w.ticks_at + 5 * kRecordedTickBytes + 268] ^= 0x01;
    std::string path = temp_path("bit.trdxrec");
    save(path, b);
    expect_refused(path, {"checksum mismatch", "corrupted"});
    // The same in the header text (a letter of the device name) and in the stored checksum itself.
    b = w.bytes;
    b[32 + 17] ^= 0x01;
    path = temp_path("bit_header.trdxrec");
    save(path, b);
    expect_refused(path, {"checksum mismatch"});
    b = w.bytes;
    b[24] ^= 0x80;
    path = temp_path("bit_crc.trdxrec");
    save(path, b);
    expect_refused(path, {"checksum mismatch"});
}

TEST(Recording, BadHeaderTextRefused) {
    const Written w = write_sample("good.trdxrec", 2);
    std::vector<unsigned char> b = w.bytes;
    b[32] = '[';  // the JSON object's opening brace becomes an unbalanced bracket
    std::string path = temp_path("json.trdxrec");
    save(path, b);
    expect_refused(path, {"header text (byte 32)", "not JSON"});
    // A header whose period_s is not positive (written by hand: the writer refuses it).
    const std::string text = R"({"device_name":"x","period_s":-1,"workspace_mode":"m","notes":""})";
    b.assign(w.bytes.begin(), w.bytes.begin() + 32);
    b[28] = static_cast<unsigned char>(text.size()), b[29] = b[30] = b[31] = 0;
    b[16] = 0;  // zero ticks
    b.insert(b.end(), text.begin(), text.end());
    const std::uint32_t crc = crc32_ieee(text.data(), text.size());
    for (int i = 0; i < 4; ++i) b[24 + i] = static_cast<unsigned char>(crc >> (8 * i));
    path = temp_path("period.trdxrec");
    save(path, b);
    expect_refused(path, {"header text", "period_s = -1"});
}

TEST(Recording, MarksRoundTripAndBadMarksAreRefused) {
    Recording src = sample_recording(3);
    src.header.marks = std::vector<RecordedMark>{{0, "end_stroke"}, {2, "undo"}, {2, "redo"}};
    std::string path = temp_path("marks.trdxrec");
    write_recording(path, src);
    Recording back = read_recording(path);
    ASSERT_TRUE(back.header.marks.has_value());
    ASSERT_EQ(back.header.marks->size(), 3u);
    EXPECT_EQ((*back.header.marks)[1].after_samples, 2u);
    EXPECT_EQ((*back.header.marks)[1].kind, "undo");
    EXPECT_EQ((*back.header.marks)[2].kind, "redo");
    // The app's menu track rides along as JSON text; a track that is not an array is refused.
    src.header.menu = R"([{"t_s":1.5,"shown":false}])";
    write_recording(path, src);
    EXPECT_EQ(nlohmann::json::parse(read_recording(path).header.menu), nlohmann::json::parse(src.header.menu));
    src.header.menu = R"({"t_s":1})";
    EXPECT_THROW(write_recording(path, src), Error);
    src.header.menu.clear();
    // No marks (a file from before they were kept) reads as none, not as an empty list.
    src.header.marks.reset();
    write_recording(path, src);
    EXPECT_FALSE(read_recording(path).header.marks.has_value());
    // The writer refuses what the reader would.
    src.header.marks = std::vector<RecordedMark>{{5, "undo"}, {4, "redo"}};
    EXPECT_THROW(write_recording(temp_path("w.trdxrec"), src), Error);
    src.header.marks = std::vector<RecordedMark>{{5, "save"}};
    EXPECT_THROW(write_recording(temp_path("w.trdxrec"), src), Error);

    // Hand-written headers with bad marks: each refused naming the mark and the field.
    const Written w = write_sample("good.trdxrec", 2);
    const auto with_header = [&](const std::string& name, const std::string& text) {
        return file_with_header(w, name, text);
    };
    const std::string head = R"({"device_name":"x","period_s":0.001,"workspace_mode":"m","notes":"","marks":)";
    expect_refused(with_header("m1.trdxrec", head + R"({"a":1}})"), {"\"marks\" is not an array"});
    expect_refused(with_header("m2.trdxrec", head + R"([{"after_samples":3,"kind":"undo"},{"after_samples":2,"kind":"redo"}]})"),
                   {"marks[1].after_samples = 2", "less than the mark before it (3)"});
    expect_refused(with_header("m3.trdxrec", head + R"([{"after_samples":-1,"kind":"undo"}]})"),
                   {"marks[0].after_samples missing or not an integer >= 0"});
    expect_refused(with_header("m4.trdxrec", head + R"([{"after_samples":1,"kind":"save"}]})"),
                   {"marks[0].kind missing or not"});
    expect_refused(with_header("m5.trdxrec", head + R"([7]})"), {"marks[0] is not an object"});
}

TEST(Recording, PoseSetsRoundTripBitForBitAndBadOnesAreRefused) {
    Recording src = sample_recording(2);
    const Quat turn = glm::normalize(Quat(0.9, 0.1, -0.3, 0.2));
    src.header.poses = {RecordedPose{125, 0.125, 0, Pose{Vec3(0.1, -1.0 / 3.0, 0.05), Quat(1.0, 0.0, 0.0, 0.0)}},
                        RecordedPose{500, 0.125, 3, Pose{Vec3(1e-9, 0.0, 2.0 / 7.0), turn}}};
    const std::string path = temp_path("poses.trdxrec");
    write_recording(path, src);
    const Recording back = read_recording(path);
    ASSERT_EQ(back.header.poses.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
        EXPECT_EQ(back.header.poses[k].tick, src.header.poses[k].tick);
        EXPECT_EQ(back.header.poses[k].device_t_s, src.header.poses[k].device_t_s);  // a stalled clock may repeat
        EXPECT_EQ(back.header.poses[k].workpiece, src.header.poses[k].workpiece);
        EXPECT_EQ(back.header.poses[k].pose.position, src.header.poses[k].pose.position);  // bit for bit
        EXPECT_EQ(back.header.poses[k].pose.orientation, src.header.poses[k].pose.orientation);
    }
    // The writer refuses what the reader would.
    Recording bad = src;
    bad.header.poses[1].tick = 100;
    EXPECT_THROW(write_recording(temp_path("w.trdxrec"), bad), Error);
    bad = src;
    bad.header.poses[0].pose.orientation = Quat(2.0, 0.0, 0.0, 0.0);
    EXPECT_THROW(write_recording(temp_path("w.trdxrec"), bad), Error);

    const Written w = write_sample("good_poses.trdxrec", 2);
    const auto with_header = [&](const std::string& name, const std::string& text) {
        return file_with_header(w, name, text);
    };
    const std::string head = R"({"device_name":"x","period_s":0.001,"workspace_mode":"m","notes":"","poses":)";
    const std::string one = R"("t_s":1,"workpiece":0,"position_m":[0,0,0],"orientation":[1,0,0,0])";
    expect_refused(with_header("p1.trdxrec", head + R"({"a":1}})"), {"\"poses\" is not an array"});
    expect_refused(with_header("p2.trdxrec", head + "[{\"tick\":9," + one + "},{\"tick\":8," + one + "}]}"),
                   {"poses[1].tick = 8 decreases"});
    expect_refused(with_header("p3.trdxrec", head + R"([{"tick":1,"t_s":1,"workpiece":9,"position_m":[0,0,0],"orientation":[1,0,0,0]}]})"),
                   {"poses[0].workpiece missing or not an integer 0..7"});
    expect_refused(with_header("p4.trdxrec", head + R"([{"tick":1,"t_s":1,"workpiece":0,"position_m":[0,0],"orientation":[1,0,0,0]}]})"),
                   {"poses[0].position_m missing or not 3 numbers"});
    expect_refused(with_header("p5.trdxrec", head + R"([{"tick":1,"t_s":1,"workpiece":0,"position_m":[0,0,0],"orientation":[1,1,0,0]}]})"),
                   {"poses[0].orientation is not a unit quaternion"});
    expect_refused(with_header("p6.trdxrec", head + R"([{"tick":1,"workpiece":0,"position_m":[0,0,0],"orientation":[1,0,0,0]}]})"),
                   {"poses[0].t_s missing or not a number"});
    expect_refused(with_header("p7.trdxrec", head + "[{" + one + "}]}"), {"poses[0].tick missing or not an integer >= 0"});
}

TEST(RecordingWriter, RefusesBadTicksAndKeepsTheFileValid) {
    const std::string path = temp_path("w.trdxrec");
    Recording src = sample_recording(4);
    {
        RecordingWriter w(path, src.header);
        w.write(src.ticks[0]);
        RecordedTick bad = src.ticks[1];
        bad.force_n.y = kNaN;
        try {
            w.write(bad);
            ADD_FAILURE() << "NaN force accepted";
        } catch (const Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind(path + ": tick 1: force_n = (", 0), 0u) << e.what();
        }
        bad = src.ticks[1];
        bad.t_s = src.ticks[0].t_s;
        EXPECT_THROW(w.write(bad), Error);
        bad = src.ticks[1];
        bad.device.velocity_m_s.x = kNaN;  // valid == 1
        EXPECT_THROW(w.write(bad), Error);
        bad.valid = 0;  // the same sample, flagged invalid, is recordable
        w.write(bad);
        src.ticks[1] = bad;
        w.write(src.ticks[2]);
        w.write(src.ticks[3]);
        EXPECT_EQ(w.ticks_written(), 4u);
        w.close();
        w.close();  // idempotent
        EXPECT_THROW(w.write(src.ticks[3]), Error);
    }
    const Recording back = read_recording(path);
    ASSERT_EQ(back.ticks.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) expect_identical(src.ticks[i], back.ticks[i], i);
}

TEST(RecordingWriter, RefusesBadHeaderAndPath) {
    RecordingHeader h;
    h.period_s = 0.0;
    const std::string path = temp_path("h.trdxrec");
    EXPECT_THROW(RecordingWriter(path, h), Error);
    h.period_s = 1e-3;
    h.notes = "bad utf-8 \xFF\xFE";
    try {
        RecordingWriter w(path, h);
        ADD_FAILURE() << "invalid UTF-8 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("UTF-8"), std::string::npos) << e.what();
    }
    h.notes.clear();
    const std::string bad_dir = temp_path("no_such_dir") + "/x.trdxrec";
    try {
        RecordingWriter w(bad_dir, h);
        ADD_FAILURE() << "unwritable path accepted";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(bad_dir + ": cannot create", 0), 0u) << e.what();
    }
}

TEST(RecordingWriter, DestructorFinishesUnlessUnwinding) {
    const Recording src = sample_recording(3);
    const std::string done = temp_path("done.trdxrec");
    {
        RecordingWriter w(done, src.header);
        for (const RecordedTick& t : src.ticks) w.write(t);
    }  // no close(): the destructor finishes the file
    EXPECT_EQ(read_recording(done).ticks.size(), 3u);

    // A session that failed while recording leaves the previous file as it was, and no cut one.
    const std::string aborted = temp_path("aborted.trdxrec");
    write_recording(aborted, sample_recording(2));
    try {
        RecordingWriter w(aborted, src.header);
        for (const RecordedTick& t : src.ticks) w.write(t);
        throw std::runtime_error("session failed");
    } catch (const std::runtime_error&) {
    }
    EXPECT_EQ(read_recording(aborted).ticks.size(), 2u) << "the failed session's recording replaced the previous one";
    std::size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(aborted).parent_path()))
        files += e.path().filename().string().rfind(std::filesystem::path(aborted).filename().string(), 0) == 0;
    EXPECT_EQ(files, 1u) << "a temporary file of the failed recording was left";
}

// Splits one CSV line at commas (the export never quotes).
std::vector<std::string> fields(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream ss(line);
    std::string f;
    while (std::getline(ss, f, ',')) out.push_back(f);
    return out;
}

TEST(RecordingCsv, HeaderAndOneRowPerTick) {
    const Recording src = sample_recording(20);
    const std::string path = temp_path("r.csv");
    write_recording_csv(path, src);
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    ASSERT_EQ(lines.size(), src.ticks.size() + 1);
    const std::vector<std::string>& cols = recording_csv_columns();
    EXPECT_EQ(cols.size(), 56u);  // 13 device columns, 33 Table 3 columns, 5 more, 5 of the tool in use
    EXPECT_EQ(fields(lines[0]), cols);
    const auto col = [&](const std::string& name) {
        for (std::size_t i = 0; i < cols.size(); ++i)
            if (cols[i] == name) return i;
        ADD_FAILURE() << "no column " << name;
        return std::size_t{0};
    };
    for (const char* name : {"wand_centre_x_m", "rotation_angle_rad", "top_collision_y_m", "bottom_deviation_m",
                             "force_z_n", "torque_x_nm", "top_collision_id", "tool_mode"})
        col(name);
    for (std::size_t i = 0; i < src.ticks.size(); ++i) {
        SCOPED_TRACE(i);
        const std::vector<std::string> f = fields(lines[i + 1]);
        ASSERT_EQ(f.size(), cols.size());
        const RecordedTick& t = src.ticks[i];
        // 17 significant digits read back to the same double.
        EXPECT_TRUE(same_bits(std::strtod(f[col("t_s")].c_str(), nullptr), t.t_s));
        EXPECT_TRUE(same_bits(std::strtod(f[col("top_force_z_n")].c_str(), nullptr), t.top_force_n.z));
        EXPECT_TRUE(same_bits(std::strtod(f[col("device_vy_m_s")].c_str(), nullptr), t.device.velocity_m_s.y));
        EXPECT_EQ(std::stoll(f[col("bottom_collision_id")]), t.bottom_collision_id);
        EXPECT_EQ(std::stoull(f[col("buttons")]), t.buttons);
        EXPECT_EQ(std::stoi(f[col("valid")]), t.valid);
        EXPECT_EQ(std::stoi(f[col("op")]), t.op);
        EXPECT_TRUE(same_bits(std::strtod(f[col("tool_radius_m")].c_str(), nullptr), t.tool.radius_m));
        if (t.valid == 0) {
            EXPECT_EQ(f[col("device_x_m")], "nan");
            EXPECT_EQ(f[col("device_z_m")], "inf");
        }
    }
    EXPECT_THROW(write_recording_csv(temp_path("no_dir") + "/r.csv", src), Error);
}

}  // namespace
}  // namespace tridex::devices
