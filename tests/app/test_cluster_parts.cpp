// The parts of a cluster session that need no MPI: the messages on the wire and their checks, the cluster config and
// its errors, and records applied a frame at a time giving the same model as all at once.
#include <gtest/gtest.h>

#include <cstring>
#include <limits>

#include "app/scene/workpiece_source.hpp"
#include "app/session/cluster/cluster_config.hpp"
#include "app/session/cluster/frame_message.hpp"
#include "app/support/assets.hpp"
#include "compute/journal/journal_format.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/model/model_digest.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

// A carving pass along x through the workpiece centre `c` (ball of 6 mm), `n` samples.
std::vector<ToolSample> pass(const Vec3& c, int n, double y_offset) {
    std::vector<ToolSample> out;
    for (int i = 0; i < n; ++i) {
        ToolSample s;
        s.t_s = 0.001 * i;
        s.position = c + Vec3(-0.06 + 0.12 * i / (n - 1), y_offset, 0.0);
        s.tool.radius_m = 0.006;
        s.op = ToolOp::kSubtract;
        out.push_back(s);
    }
    return out;
}

// Records of two strokes, split into batches of `per` samples.
std::vector<compute::JournalRecord> two_strokes(const Vec3& c, std::size_t per) {
    std::vector<compute::JournalRecord> out;
    auto add_batches = [&](const std::vector<ToolSample>& s) {
        for (std::size_t i = 0; i < s.size(); i += per) {
            compute::JournalRecord r;
            r.kind = compute::JournalKind::kBatch;
            r.index = out.size();
            r.samples.assign(s.begin() + static_cast<std::ptrdiff_t>(i), s.begin() + static_cast<std::ptrdiff_t>(std::min(s.size(), i + per)));
            out.push_back(std::move(r));
        }
    };
    auto add_mark = [&](compute::JournalKind k, std::uint64_t serial) {
        compute::JournalRecord r;
        r.kind = k;
        r.index = out.size();
        r.serial = serial;
        out.push_back(std::move(r));
    };
    add_batches(pass(c, 40, 0.0));
    add_mark(compute::JournalKind::kStrokeEnd, 1);
    add_batches(pass(c, 40, 0.02));
    add_mark(compute::JournalKind::kStrokeEnd, 2);
    return out;
}

TEST(ClusterParts, RecordsAppliedFrameByFrameGiveTheModelOfAllAtOnce) {
    Workpiece wp = prepare_workpiece(default_mesh_path(), 40, 0.2, Vec3(0.0));
    const Vec3 c = wp.model.lattice.bounds().centre();
    const std::vector<compute::JournalRecord> records = two_strokes(c, 7);
    const std::uint64_t start = compute::model_digest(wp.model);

    compute::TriDexel all = wp.model;
    (void)compute::journal_apply(all, records);
    EXPECT_NE(compute::model_digest(all), start) << "the passes cut nothing";

    compute::TriDexel frames = wp.model;
    compute::JournalApplier applier(frames);
    for (std::size_t i = 0; i < records.size(); i += 3)
        applier.apply(std::span<const compute::JournalRecord>(records).subspan(i, std::min<std::size_t>(3, records.size() - i)));
    applier.flush();
    EXPECT_EQ(compute::model_digest(frames), compute::model_digest(all));
    EXPECT_EQ(applier.stats().strokes, 2u);
    EXPECT_EQ(applier.stats().samples, 80u);

    // A model that differs in one interval end differs in its digest.
    compute::TriDexel touched = all;
    for (auto& ray : touched.sets[0].rays)
        if (!ray.empty()) {
            ray[0].exit = std::nextafter(ray[0].exit, 1e9f);
            break;
        }
    EXPECT_NE(compute::model_digest(touched), compute::model_digest(all));
}

FrameMessage sample_frame() {
    FrameMessage m;
    m.frame = 41;
    m.head.position = Vec3(0.1, 1.7, 2.0);
    m.nav_scale = 1.5;
    m.eye_separation_m = 0.064;
    m.tool_m = Vec3(0.0, 1.3, 0.7);
    m.tool.radius_m = 0.008;
    m.ao = 0.5;
    m.records = two_strokes(Vec3(0.0), 16);
    m.check_digest = 0x1234567890abcdefull;
    m.check_after = 2;
    m.sent_s = 12.5;
    return m;
}

TEST(ClusterParts, AFrameMessageRoundTripsBitForBit) {
    const FrameMessage m = sample_frame();
    const std::vector<unsigned char> bytes = encode_frame(m);
    std::size_t samples = 0, marks = 0;
    for (const compute::JournalRecord& r : m.records) (r.kind == compute::JournalKind::kBatch ? samples += r.samples.size() : ++marks);
    EXPECT_EQ(bytes.size(), frame_message_bytes(m.records.size() - marks, samples, marks));
    const FrameMessage back = decode_frame(bytes, "test");
    EXPECT_EQ(encode_frame(back), bytes);
    EXPECT_EQ(back.frame, 41u);
    ASSERT_TRUE(back.check_digest.has_value());
    EXPECT_EQ(*back.check_digest, *m.check_digest);
    ASSERT_EQ(back.records.size(), m.records.size());
    EXPECT_EQ(back.records[0].samples[3].position.x, m.records[0].samples[3].position.x);
    EXPECT_EQ(back.records[3].kind, compute::JournalKind::kStrokeEnd);
    // With the pie menu shown: its ring, path, lit slice and status go along, bit for bit.
    FrameMessage with_menu = m;
    with_menu.menu.shown = true;
    with_menu.menu.centre_m = Vec3(0.1, 1.3, 0.7);
    with_menu.menu.normal = Vec3(0.0, 0.6, 0.8);
    with_menu.menu.radius_m = 0.05;
    with_menu.menu.dead_radius_m = 0.012;
    with_menu.menu.path = {0};
    with_menu.menu.highlighted = 1;
    with_menu.menu.status = "operation: union";
    const FrameMessage menu_back = decode_frame(encode_frame(with_menu), "test");
    EXPECT_EQ(menu_back.menu, with_menu.menu);
    EXPECT_FALSE(back.menu.shown);
    // A posed workpiece: its pose goes along bit for bit; an unposed one costs no bytes.
    FrameMessage posed = m;
    posed.workpiece_pose = Pose{Vec3(0.1, -0.02, 0.3), glm::angleAxis(0.4, glm::normalize(Vec3(1.0, 2.0, 3.0)))};
    const std::vector<unsigned char> posed_bytes = encode_frame(posed);
    EXPECT_EQ(posed_bytes.size(), bytes.size() + 7 * 8);
    const FrameMessage posed_back = decode_frame(posed_bytes, "test");
    EXPECT_EQ(posed_back.workpiece_pose.position, posed.workpiece_pose.position);
    EXPECT_NEAR(glm::length(glm::vec<4, double>(posed_back.workpiece_pose.orientation.w - posed.workpiece_pose.orientation.w,
                                                posed_back.workpiece_pose.orientation.x - posed.workpiece_pose.orientation.x,
                                                posed_back.workpiece_pose.orientation.y - posed.workpiece_pose.orientation.y,
                                                posed_back.workpiece_pose.orientation.z - posed.workpiece_pose.orientation.z)),
                0.0, 1e-15);
    EXPECT_TRUE(back.workpiece_pose.is_identity());
    std::vector<unsigned char> bad = encode_frame(with_menu);
    bad.resize(bad.size() - 4);  // a cut status
    EXPECT_THROW((void)decode_frame(bad, "test"), Error);
    // A shared session's other sites, one with a tracked head, go along as rank 0 heard them.
    FrameMessage with_others = m;
    SitePresence bo;
    bo.site = 1;
    bo.name = "Bo";
    bo.colour = Vec3(0.5, 0.2, 0.9);
    bo.tool = Pose{Vec3(0.01, 1.3, 0.7), Quat(1, 0, 0, 0)};
    bo.tool_radius_m = 0.006;
    bo.head_tracked = true;
    bo.head = Pose{Vec3(0.0, 1.7, 2.0), Quat(1, 0, 0, 0)};
    bo.head_size_m = kHeadRadiusM;
    with_others.others = {bo};
    const FrameMessage others_back = decode_frame(encode_frame(with_others), "test");
    ASSERT_EQ(others_back.others.size(), 1u);
    EXPECT_EQ(others_back.others[0].name, "Bo");
    EXPECT_EQ(others_back.others[0].head.position, bo.head.position);
    EXPECT_EQ(encode_frame(others_back), encode_frame(with_others));
    bo.head_size_m = 0.0;
    with_others.others = {bo};
    EXPECT_THROW((void)decode_frame(encode_frame(with_others), "test"), Error);
    // The hello carries the bytes of the model file the session started from.
    HelloMessage h{"{}", 77, {1, 2, 3}};
    EXPECT_EQ(decode_hello(encode_hello(h), "test").model_tdx, h.model_tdx);
    // A late start's hello: where the stream goes on, the undo history (packed on the wire), each site's last sample.
    h.first_record = 1234;
    h.history.assign(5000, 7);
    h.prevs = pass(Vec3(0.1, 0.2, 0.3), 2, 0.0);
    h.prevs[1].site = 3;
    h.last_closed_serial = 17;
    const std::vector<unsigned char> late = encode_hello(h);
    EXPECT_LT(late.size(), 2000u) << "the history is packed";
    const HelloMessage late_back = decode_hello(late, "test");
    EXPECT_EQ(late_back.first_record, 1234u);
    EXPECT_EQ(late_back.history, h.history);
    ASSERT_EQ(late_back.prevs.size(), 2u);
    EXPECT_EQ(late_back.prevs[1].site, 3u);
    EXPECT_EQ(late_back.prevs[0].position, h.prevs[0].position);
    EXPECT_EQ(late_back.last_closed_serial, 17u);
    // Rank 0's word to a render rank it lets go, told apart from every other message.
    EXPECT_EQ(let_go_reason(encode_let_go("at frame 9: it hung")).value_or(""), "at frame 9: it hung");
    EXPECT_FALSE(let_go_reason(late).has_value());
    EXPECT_FALSE(let_go_reason(encode_go(3)).has_value());
    EXPECT_FALSE(let_go_reason(std::vector<unsigned char>{}).has_value());
    std::vector<unsigned char> torn = encode_let_go("at frame 9: it hung");
    torn.resize(torn.size() - 3);
    EXPECT_EQ(let_go_reason(torn).value_or(""), "(its reason could not be read)");
    HelloMessage no_model = h;
    no_model.model_tdx.clear();
    EXPECT_THROW(decode_hello(encode_hello(no_model), "test"), Error);
}

TEST(ClusterParts, ABadMessageIsRefusedNamingItsField) {
    const std::vector<unsigned char> good = encode_frame(sample_frame());
    // Every truncation is refused, none crashes.
    for (std::size_t n = 0; n < good.size(); n += 37)
        EXPECT_THROW((void)decode_frame(std::span<const unsigned char>(good.data(), n), "rank 0"), Error) << n;
    std::vector<unsigned char> bad = good;
    bad[0] = 'X';
    try {
        (void)decode_frame(bad, "rank 0's frame 41");
        FAIL() << "a bad magic was taken";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("rank 0's frame 41: magic"), std::string::npos) << e.what();
    }
    // A NaN head position.
    bad = good;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::memcpy(bad.data() + 14, &nan, 8);
    try {
        (void)decode_frame(bad, "rank 0");
        FAIL() << "a NaN head was taken";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("head"), std::string::npos) << e.what();
    }
    // Trailing bytes, and an answer that is not one.
    bad = good;
    bad.push_back(0);
    EXPECT_THROW((void)decode_frame(bad, "rank 0"), Error);
    EXPECT_THROW((void)decode_answer(good, "rank 1"), Error);
    RankAnswer a;
    a.error = "no Vulkan device";
    a.report_json = "{}";
    const RankAnswer back = decode_answer(encode_answer(a), "rank 1");
    EXPECT_EQ(back.error, "no Vulkan device");
    EXPECT_EQ(decode_go(encode_go(7), "rank 0"), 7u);
}

TEST(ClusterParts, AConfigSplitsTheWallAndItsErrorsNameTheField) {
    renderer::DisplayConfig wall = renderer::DisplayConfig::powerwall();
    wall.width_px = 400;
    wall.height_px = 300;
    wall.swap_eyes = true;
    const ClusterConfig c = parse_cluster_config(
        R"({"check_every_frames": 10, "ranks": [
              {"rank": 2, "viewports": [{"name": "right", "region": [0.5, 0, 1, 1], "eye": "right", "swap_eyes": false}]},
              {"rank": 1, "viewports": [{"name": "left", "region": [0, 0, 0.5, 1]},
                                        {"name": "top", "corners": {"lower_left": [-1, 0, 0], "lower_right": [1, 0, 0],
                                                                    "upper_left": [-1, 1, 0]}, "width_px": 64, "height_px": 32}]}]})",
        "wall.json", wall);
    ASSERT_EQ(c.ranks.size(), 2u);
    EXPECT_EQ(c.ranks[0].rank, 1);
    EXPECT_EQ(c.check_every_frames, 10);
    const ClusterViewport& left = c.ranks[0].viewports[0];
    EXPECT_EQ(left.width_px, 200);
    EXPECT_EQ(left.height_px, 300);
    EXPECT_NEAR(left.screen.lower_right.x, 0.5 * (wall.screen.lower_left.x + wall.screen.lower_right.x), 1e-12);
    EXPECT_EQ(c.ranks[1].viewports[0].eye, ViewportEye::kRight);
    EXPECT_TRUE(left.swap_eyes) << "the display config's swap_eyes is the default";
    EXPECT_FALSE(c.ranks[1].viewports[0].swap_eyes);
    EXPECT_EQ(c.ranks[1].viewports[0].stereo, renderer::StereoOutput::kMono);
    EXPECT_EQ(c.ranks[0].viewports[1].width_px, 64);
    EXPECT_EQ(c.lod, "on") << "levels of detail on the render ranks by default";
    EXPECT_EQ(c.startup, "coarse") << "render ranks start coarse first by default, as run --startup";
    EXPECT_EQ(c.stroke_contour, "coarse") << "render ranks draw strokes coarse by default, as run --stroke-contour";

    const auto error_of = [&](const std::string& text) {
        try {
            (void)parse_cluster_config(text, "wall.json", wall);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    EXPECT_NE(error_of(R"({"ranks": [{"rank": 2, "viewports": [{"name": "a", "region": [0,0,1,1]}]}]})").find("rank 1 is missing"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1,1]}, {"name": "a", "region": [0,0,1,1]}]}]})")
                  .find("ranks[0].viewports[1].name"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"lod": "fine", "ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1,1]}]}]})")
                  .find("'lod': must be on, off, coarse or simplified, got \"fine\""),
              std::string::npos)
        << error_of(R"({"lod": "fine", "ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1,1]}]}]})");
    EXPECT_NE(
        error_of(R"({"startup": "lazy", "ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1,1]}]}]})")
            .find("'startup': must be coarse or full, got 'lazy'"),
        std::string::npos)
        << error_of(
               R"({"startup": "lazy", "ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1,1]}]}]})");
    const std::string fine_strokes = error_of(
        R"({"stroke_contour": "fine", "ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1,1]}]}]})");
    EXPECT_NE(fine_strokes.find("'stroke_contour': must be coarse or full, got 'fine'"), std::string::npos)
        << fine_strokes;
    EXPECT_NE(error_of(R"({"ranks": [{"rank": 1, "viewports": [{"name": "a"}]}]})").find("either 'region' or 'corners'"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1,1], "colour": 1}]}]})")
                  .find("ranks[0].viewports[0].colour': unknown field"),
              std::string::npos);
    EXPECT_NE(error_of(R"({"ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1,1]}]}], "timeout_s": 0})")
                  .find("'timeout_s'"),
              std::string::npos);
    EXPECT_NE(error_of("{").find("not valid JSON"), std::string::npos);
    EXPECT_NE(error_of(R"({"ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1e400,1]}]}]})")
                  .find("not valid JSON: number overflow at line 1, column 67, field 'ranks[0].viewports[0].region[2]'"),
              std::string::npos)
        << error_of(R"({"ranks": [{"rank": 1, "viewports": [{"name": "a", "region": [0,0,1e400,1]}]}]})");
}

}  // namespace
}  // namespace tridex::app
