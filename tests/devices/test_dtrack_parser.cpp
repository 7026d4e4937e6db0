// Tests of devices/tracking/dtrack_parser: hand-written DTrack ASCII datagrams are read in SI units with the
// column-wise rotation, every malformed kind is rejected with its reason, 64 KiB of junk never crashes, and the
// parse cost per datagram is printed.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "devices/tracking/dtrack_parser.hpp"

namespace tridex::devices {
namespace {

// A head body 0 at (100, 1650, 900) mm rotated 90 degrees about +y (x -> -z, z -> +x), and body 3 untracked.
// Column-wise: b0..b2 is the image of x (0, 0, -1), b3..b5 of y (0, 1, 0), b6..b8 of z (1, 0, 0).
const char* kGood =
    "fr 21753\r\n"
    "ts 39596.024831\r\n"
    "6dcal 4\r\n"
    "6d 2 [0 1.000][100.000 1650.000 900.000 0.0000 90.0000 0.0000][0.000000 0.000000 -1.000000 0.000000 1.000000 "
    "0.000000 1.000000 0.000000 0.000000] [3 -1.000][0.000 0.000 0.000 0.0000 0.0000 0.0000][0 0 0 0 0 0 0 0 0]\r\n"
    "6df2 1 1 [0 0.950 8 2][-250.500 1200.000 600.250][1 0 0 0 1 0 0 0 1][5 0.500 -1.000]\r\n"
    "3d 1 [12 1.000][1.0 2.0 3.0]\r\n";

DTrackParseResult parse(const std::string& s, DTrackFrame& f) { return parse_dtrack_datagram(s, f); }

DTrackReject reason(const std::string& s) {
    DTrackFrame f;
    return parse(s, f).reason;
}

TEST(DTrackParser, ReadsEveryLineInSiUnits) {
    DTrackFrame f;
    const DTrackParseResult r = parse(kGood, f);
    ASSERT_TRUE(r.ok()) << to_string(r.reason) << " at line " << r.line;
    EXPECT_TRUE(f.has_frame_counter);
    EXPECT_EQ(f.frame_counter, 21753u);
    EXPECT_TRUE(f.has_timestamp);
    EXPECT_DOUBLE_EQ(f.timestamp_s, 39596.024831);
    EXPECT_EQ(f.calibrated_bodies, 4);
    ASSERT_EQ(f.bodies.size(), 2u);
    const DTrackBody* head = f.body(0);
    ASSERT_NE(head, nullptr);
    EXPECT_TRUE(head->tracked());
    EXPECT_DOUBLE_EQ(head->quality, 1.0);
    EXPECT_NEAR(head->position_m.x, 0.100, 1e-12);
    EXPECT_NEAR(head->position_m.y, 1.650, 1e-12);
    EXPECT_NEAR(head->position_m.z, 0.900, 1e-12);
    // Column-wise: the body's x axis maps to tracker -z, its z axis to tracker +x.
    const Pose p = head->pose();
    const Vec3 x = p.rotate(Vec3(1, 0, 0)), z = p.rotate(Vec3(0, 0, 1));
    EXPECT_NEAR(x.z, -1.0, 1e-12);
    EXPECT_NEAR(z.x, 1.0, 1e-12);
    EXPECT_NEAR(glm::length(p.orientation), 1.0, 1e-12);
    const DTrackBody* off = f.body(3);
    ASSERT_NE(off, nullptr);
    EXPECT_FALSE(off->tracked());
    EXPECT_EQ(f.body(1), nullptr);
    ASSERT_EQ(f.flysticks.size(), 1u);
    const DTrackFlystick& fs = f.flysticks[0];
    EXPECT_EQ(f.flysticks_defined, 1);
    EXPECT_NEAR(fs.body.position_m.x, -0.2505, 1e-12);
    EXPECT_EQ(fs.button_count, 8);
    EXPECT_EQ(fs.buttons, 5u);
    EXPECT_EQ(fs.controller_count, 2);
    EXPECT_DOUBLE_EQ(fs.controllers[0], 0.5);
    EXPECT_DOUBLE_EQ(fs.controllers[1], -1.0);
    EXPECT_EQ(f.ignored_lines, 1);
}

TEST(DTrackParser, AcceptsLfEndingsLocationWithoutAnglesAndEmptyBodyLists) {
    DTrackFrame f;
    EXPECT_TRUE(parse("fr 1\n6d 1 [2 0.5][1 2 3][1 0 0 0 1 0 0 0 1]\n", f).ok());
    ASSERT_EQ(f.bodies.size(), 1u);
    EXPECT_EQ(f.bodies[0].id, 2);
    EXPECT_TRUE(parse("fr 2\r\n6d 0\r\n6df2 0 0\r\n", f).ok());
    EXPECT_TRUE(f.bodies.empty());
    EXPECT_TRUE(parse("6df2 2 1 [1 1.0 0 0][0 0 0][1 0 0 0 1 0 0 0 1][]", f).ok());
}

TEST(DTrackParser, ParsingAgainReusesTheFrame) {
    DTrackFrame f;
    ASSERT_TRUE(parse(kGood, f).ok());
    ASSERT_TRUE(parse("fr 7\r\n", f).ok());
    EXPECT_TRUE(f.bodies.empty());
    EXPECT_TRUE(f.flysticks.empty());
    EXPECT_FALSE(f.has_timestamp);
    EXPECT_EQ(f.calibrated_bodies, -1);
}

struct Bad {
    std::string datagram;
    DTrackReject reason;
};

class DTrackParserRejects : public ::testing::TestWithParam<Bad> {};

TEST_P(DTrackParserRejects, WithItsReason) {
    DTrackFrame f;
    const DTrackParseResult r = parse(GetParam().datagram, f);
    EXPECT_FALSE(r.ok());
    EXPECT_EQ(r.reason, GetParam().reason) << "got " << to_string(r.reason) << " for: " << GetParam().datagram;
}

INSTANTIATE_TEST_SUITE_P(
    Malformed, DTrackParserRejects,
    ::testing::Values(
        Bad{"", DTrackReject::kEmpty}, Bad{"\r\n\r\n  \n", DTrackReject::kEmpty},
        Bad{"fr 1\r\n\x01\x02\x03", DTrackReject::kNotText}, Bad{"fr 1\r\n6d 0\xc3\xa9", DTrackReject::kNotText},
        Bad{"hello world\r\n", DTrackReject::kUnknownLine}, Bad{"fr 1\r\nFR 2\r\n", DTrackReject::kUnknownLine},
        // truncated: mid-line, mid-block, mid-matrix
        Bad{"fr\r\n", DTrackReject::kTruncated}, Bad{"6d 1 [0 1.0][1 2 3][1 0 0 0 1", DTrackReject::kTruncated},
        Bad{"6d 1 [0 1.0][1 2", DTrackReject::kTruncated}, Bad{"6d 1 [0", DTrackReject::kTruncated},
        Bad{"6d 1 [0 1.0][1 2 3][1 0 0 0 1 0 0 0]", DTrackReject::kTruncated},
        Bad{"6df2 1 1 [0 1.0 8 2][0 0 0][1 0 0 0 1 0 0 0 1][1 0.5", DTrackReject::kTruncated},
        // non-numeric
        Bad{"fr abc\r\n", DTrackReject::kNotNumeric},
        Bad{"6d 1 [0 1.0][1 2 x][1 0 0 0 1 0 0 0 1]", DTrackReject::kNotNumeric},
        Bad{"6d 1 [0 1.0][1 2 3.5.6][1 0 0 0 1 0 0 0 1]", DTrackReject::kNotNumeric},
        Bad{"fr 1.5\r\n", DTrackReject::kNotNumeric}, Bad{"6d one\r\n", DTrackReject::kNotNumeric},
        // NaN and infinity
        Bad{"6d 1 [0 1.0][nan 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kNotFinite},
        Bad{"6d 1 [0 1.0][1 2 3][1 0 0 0 inf 0 0 0 1]", DTrackReject::kNotFinite},
        Bad{"ts NaN\r\n", DTrackReject::kNotFinite},
        Bad{"6d 1 [0 nan][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kNotFinite},
        // syntax
        Bad{"6d 1 (0 1.0)[1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kSyntax},
        Bad{"6d 1 [0 1.0][1 2 3 4][1 0 0 0 1 0 0 0 1]", DTrackReject::kSyntax},
        Bad{"6d 1 [0 1.0 7 x][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kNotNumeric},
        Bad{"6d 1 [0 1.0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kSyntax},
        Bad{"fr 1\r\nts2 1700000000 250000 1200\r\nts2 1700000000 250000 1200\r\n", DTrackReject::kDuplicate},
        Bad{"ts2 1700000000 1000000 0\r\n", DTrackReject::kOutOfRange},
        Bad{"ts2 1700000000 250000\r\n", DTrackReject::kTruncated},
        Bad{std::string("fr 1\r\n\0\r\n6d 0\r\n", 12), DTrackReject::kNotText},  // a NUL before the end
        Bad{"6d 1 [0 1.0][1 2 3][1 0 0 0 1 0 0 0 1 0]", DTrackReject::kSyntax},
        Bad{"fr 1 2\r\n", DTrackReject::kSyntax},
        Bad{"6d 1 [0 1.0][1 2 3][1 0 0 0 1 0 0 0 1] x", DTrackReject::kSyntax},
        Bad{"fr 1\r6d 0\r\n", DTrackReject::kSyntax},
        // wrong body counts
        Bad{"6d 2 [0 1.0][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kBodyCount},
        Bad{"6d 1 [0 1.0][1 2 3][1 0 0 0 1 0 0 0 1][1 1.0][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kBodyCount},
        Bad{"6dcal 1\r\n6d 2 [0 1.0][1 2 3][1 0 0 0 1 0 0 0 1][1 1.0][1 2 3][1 0 0 0 1 0 0 0 1]",
            DTrackReject::kBodyCount},
        Bad{"6d -1\r\n", DTrackReject::kBodyCount}, Bad{"6d 100000\r\n", DTrackReject::kBodyCount},
        Bad{"6df2 1 2 [0 1.0 0 0][0 0 0][1 0 0 0 1 0 0 0 1][]", DTrackReject::kBodyCount},
        // out of range
        Bad{"6d 1 [0 1.5][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kOutOfRange},
        Bad{"6d 1 [0 -0.5][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kOutOfRange},
        Bad{"6d 1 [-1 1.0][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kOutOfRange},
        Bad{"6d 1 [256 1.0][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kOutOfRange},
        Bad{"6d 1 [0 1.0][1e9 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kOutOfRange},
        Bad{"6dcal 2\r\n6d 1 [5 1.0][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kOutOfRange},
        Bad{"fr -3\r\n", DTrackReject::kOutOfRange}, Bad{"fr 99999999999999999999999\r\n", DTrackReject::kOutOfRange},
        Bad{"6df2 1 1 [0 1.0 8 1][0 0 0][1 0 0 0 1 0 0 0 1][256 0.0]", DTrackReject::kOutOfRange},
        Bad{"6df2 1 1 [0 1.0 8 1][0 0 0][1 0 0 0 1 0 0 0 1][1 1.5]", DTrackReject::kOutOfRange},
        Bad{"6df2 1 1 [0 1.0 99 0][0 0 0][1 0 0 0 1 0 0 0 1][0 0 0 0]", DTrackReject::kOutOfRange},
        Bad{"6df2 1 1 [1 1.0 0 0][0 0 0][1 0 0 0 1 0 0 0 1][]", DTrackReject::kOutOfRange},
        // not a rotation (tracked): scaled, sheared, a reflection
        Bad{"6d 1 [0 1.0][1 2 3][2 0 0 0 1 0 0 0 1]", DTrackReject::kNotRotation},
        Bad{"6d 1 [0 1.0][1 2 3][1 0.1 0 0 1 0 0 0 1]", DTrackReject::kNotRotation},
        Bad{"6d 1 [0 1.0][1 2 3][-1 0 0 0 1 0 0 0 1]", DTrackReject::kNotRotation},
        Bad{"6d 1 [0 1.0][1 2 3][0 0 0 0 0 0 0 0 0]", DTrackReject::kNotRotation},
        // duplicates
        Bad{"fr 1\r\nfr 2\r\n", DTrackReject::kDuplicate},
        Bad{"6d 2 [0 1.0][1 2 3][1 0 0 0 1 0 0 0 1][0 1.0][1 2 3][1 0 0 0 1 0 0 0 1]", DTrackReject::kDuplicate},
        Bad{"6d 0\r\n6d 0\r\n", DTrackReject::kDuplicate}));

TEST(DTrackParser, NamesTheLineAtFault) {
    DTrackFrame f;
    const DTrackParseResult r = parse("fr 1\r\nts 2.5\r\n6d 1 [0 1.0][1 2 x][1 0 0 0 1 0 0 0 1]\r\n", f);
    EXPECT_EQ(r.reason, DTrackReject::kNotNumeric);
    EXPECT_EQ(r.line, 3);
    EXPECT_STREQ(to_string(r.reason), "not_numeric");
}

TEST(DTrackParser, TooLargeDatagramIsRejected) {
    std::string big(kDTrackMaxDatagram + 1, ' ');
    big.replace(0, 4, "fr 1");
    EXPECT_EQ(reason(big), DTrackReject::kTooLarge);
}

// 64 KiB of junk of several kinds: random bytes, random printable text, random DTrack-like tokens, and every
// prefix of a good datagram. None may crash or be accepted as anything but what it is.
TEST(DTrackParser, JunkIsRejectedNeverCrashes) {
    std::mt19937_64 rng(15);
    DTrackFrame f;
    std::string junk(64 * 1024, '\0');
    for (char& c : junk) c = static_cast<char>(rng() & 0xFF);
    EXPECT_EQ(reason(junk), DTrackReject::kNotText);
    for (char& c : junk) c = static_cast<char>(0x20 + rng() % 95);
    EXPECT_FALSE(parse(junk, f).ok());
    // Token soup: valid pieces in random order; accepted only when it happens to be well-formed.
    static const char* kPieces[] = {"6d ", "fr ",  "ts ", "6df2 ", "[",    "]",
                                    "1 ",  "0.5 ", "-1 ", "nan ",  "\r\n", "1e308 "};
    int accepted = 0;
    for (int trial = 0; trial < 200; ++trial) {
        std::string s;
        while (s.size() < 64 * 1024 / 200) s += kPieces[rng() % std::size(kPieces)];
        if (parse(s, f).ok()) ++accepted;
    }
    EXPECT_LT(accepted, 200);
    // Every prefix of a good datagram: accepted at each line end; every cut inside the 6d line is rejected.
    const std::string good = kGood;
    const std::size_t b6d = good.find("6d 2"), e6d = good.find("\r\n", b6d);
    for (std::size_t n = 1; n <= good.size(); ++n) {
        const DTrackParseResult r = parse(good.substr(0, n), f);
        if (good[n - 1] == '\n') {
            EXPECT_TRUE(r.ok()) << "prefix of " << n << " bytes: " << to_string(r.reason);
        }
        if (n > b6d && n < e6d) {
            EXPECT_FALSE(r.ok()) << "prefix of " << n << " bytes cut inside the 6d line";
        }
    }
}

// Parse cost per datagram for a typical head-tracking datagram (fr, ts, 6dcal, 6d with 2 bodies, 6df2): printed
// for the report, and bounded loosely so that a pathological slowdown fails.
TEST(DTrackParser, ParseCostPerDatagram) {
    const std::string d = kGood;
    DTrackFrame f;
    constexpr int kN = 20000;
    int ok = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kN; ++i) ok += parse_dtrack_datagram(d, f).ok() ? 1 : 0;
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / kN;
    EXPECT_EQ(ok, kN);
    std::printf("[ dtrack ] parse cost: %.2f us per datagram (%zu bytes, 2 bodies + 1 Flystick)\n", us, d.size());
    EXPECT_LT(us, 200.0);
}

}  // namespace
// Later DTracks: an extended timestamp, line types tridex does not know, and more values in an id block are read
// as ART's DTrackSDK reads them (it skips unknown lines and extra data in a block); a trailing NUL is dropped.
TEST(DTrackParser, ReadsWhatLaterDTracksSendAndSkipsWhatItDoesNotKnow) {
    DTrackFrame f;
    DTrackParseResult r = parse_dtrack_datagram("fr 7\r\nts2 1700000000 250000 1200\r\n6d 0\r\n", f);
    ASSERT_TRUE(r.ok()) << to_string(r.reason) << " line " << r.line;
    EXPECT_TRUE(f.has_timestamp);
    EXPECT_NEAR(f.timestamp_s, 1700000000 % 86400 + 0.25, 1e-9);
    EXPECT_TRUE(f.has_latency);
    EXPECT_NEAR(f.latency_s, 0.0012, 1e-12);
    r = parse_dtrack_datagram("fr 8\r\n6dx9 2 [1 2][3 4]\r\nhand 1\r\n6d 1 [0 1.0][1 2 3][1 0 0 0 1 0 0 0 1]\r\n", f);
    ASSERT_TRUE(r.ok()) << to_string(r.reason) << " line " << r.line;
    EXPECT_EQ(f.unknown_lines, 2);
    ASSERT_EQ(f.bodies.size(), 1u);
    r = parse_dtrack_datagram(
        "6d 1 [0 1.0 0.25 3][1 2 3][1 0 0 0 1 0 0 0 1]\r\n6df2 1 1 [0 1.0 8 2 9][0 0 0][1 0 0 0 1 0 0 0 1][5 0.5 -1]", f);
    ASSERT_TRUE(r.ok()) << to_string(r.reason) << " line " << r.line;
    EXPECT_EQ(f.extra_values, 3);
    ASSERT_EQ(f.bodies.size(), 1u);
    EXPECT_DOUBLE_EQ(f.bodies[0].quality, 1.0);
    ASSERT_EQ(f.flysticks.size(), 1u);
    EXPECT_EQ(f.flysticks[0].buttons, 5u);
    const std::string with_nul("fr 9\r\n6d 0\r\n\0", 14);
    r = parse_dtrack_datagram(with_nul, f);
    ASSERT_TRUE(r.ok()) << to_string(r.reason);
    EXPECT_EQ(f.frame_counter, 9u);
    // Only unknown lines: nothing tridex reads, refused with its reason.
    r = parse_dtrack_datagram("hand 1\r\nglove 2\r\n", f);
    EXPECT_EQ(r.reason, DTrackReject::kUnknownLine);
}

}  // namespace tridex::devices
