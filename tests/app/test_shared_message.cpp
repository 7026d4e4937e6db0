// A shared session's messages on the wire: each kind round-trips, a long records message travels packed (zstd) and
// smaller, and bad bytes are refused with a message naming the field: truncation, another magic or kind, a site out
// of range, a control character in a name, packed records that lie about their size or nest.
#include <gtest/gtest.h>

#include "app/session/view/presence_view.hpp"
#include "app/session/shared/shared_message.hpp"
#include "compute/journal/stream_pack.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

std::string refusal(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

PresenceMessage tool_presence(std::uint8_t site, bool gone, const std::string& name, const Vec3& colour, const Pose& tool,
                              double radius_m) {
    PresenceMessage p;
    p.site = site;
    p.gone = gone;
    p.name = name;
    p.colour = colour;
    p.tool = tool;
    p.tool_radius_m = radius_m;
    return p;
}

RecordsMessage some_records(std::size_t n) {
    RecordsMessage m;
    for (std::size_t i = 0; i < n; ++i) {
        compute::JournalRecord& r = m.records.emplace_back();
        r.index = i;
        for (int k = 0; k < 20; ++k) {
            ToolSample s;
            s.t_s = 1e-3 * static_cast<double>(20 * i + k);
            s.position = Vec3(0.01 * std::sin(s.t_s), 0.02, 0.04);
            s.op = ToolOp::kSubtract;
            s.tool.radius_m = 0.004;
            s.site = static_cast<std::uint8_t>(i % 3);
            r.samples.push_back(s);
        }
    }
    compute::JournalRecord& mark = m.records.emplace_back();
    mark.kind = compute::JournalKind::kUndo;
    mark.index = n;
    mark.serial = 4;
    mark.rays = 99;
    m.check_digest = 0x1234;
    m.check_after = 1;
    return m;
}

TEST(SharedMessage, EveryKindRoundTrips) {
    const JoinMessage j = decode_join(encode_join({kSharedProtocol, "Bo", Vec3(0.1, 0.2, 0.3)}), "t");
    EXPECT_EQ(j.name, "Bo");
    EXPECT_EQ(j.colour, Vec3(0.1, 0.2, 0.3));
    const WelcomeMessage w = decode_welcome(encode_welcome({3, "Ann", "{\"a\":1}", {9, 8, 7}, 77}), "t");
    EXPECT_EQ(w.site, 3);
    EXPECT_EQ(w.model_tdx.size(), 3u);
    EXPECT_EQ(w.initial_digest, 77u);
    EXPECT_EQ(decode_request(encode_request(SculptRequest::kRedo), "t"), SculptRequest::kRedo);
    const RecordsMessage r = decode_records(encode_records(some_records(2)), "t");
    ASSERT_EQ(r.records.size(), 3u);
    EXPECT_EQ(r.records[1].samples[5].site, 1);
    EXPECT_EQ(r.records[2].serial, 4u);
    EXPECT_EQ(*r.check_digest, 0x1234u);
    const RefusedMessage f = decode_refused(encode_refused({SculptRequest::kUndo, 2, "Cy"}), "t");
    EXPECT_EQ(f.by_name, "Cy");
    const PresenceMessage p = decode_presence(encode_presence(tool_presence(4, true, "Di", Vec3(1.0), Pose{}, 0.005)), "t");
    EXPECT_TRUE(p.gone);
    EXPECT_EQ(p.tool_radius_m, 0.005);
    EXPECT_EQ(decode_end(encode_end({5, 6, "bye"}), "t").reason, "bye");
}

TEST(SharedMessage, ALongStreamTravelsPackedAndSmaller) {
    const RecordsMessage m = some_records(400);
    const std::vector<unsigned char> b = encode_records(m);
    EXPECT_EQ(shared_kind(b, "t"), SharedKind::kRecordsPacked);
    const std::size_t plain = 400 * (1 + 8 + 4 + 20 * 120);
    EXPECT_LT(b.size(), plain / 3);
    const RecordsMessage back = decode_records(b, "t");
    ASSERT_EQ(back.records.size(), m.records.size());
    EXPECT_EQ(back.records[399].samples[19].t_s, m.records[399].samples[19].t_s);
    EXPECT_EQ(shared_kind(encode_records(some_records(1)), "t"), SharedKind::kRecords);  // short: as it is
}

TEST(SharedMessage, BadBytesAreRefusedNamingTheField) {
    std::vector<unsigned char> j = encode_join({kSharedProtocol, "Bo", Vec3(0.5)});
    EXPECT_NE(refusal([&] { decode_join(std::span(j).first(j.size() - 3), "peer"); }).find("peer: colour: truncated"),
              std::string::npos);
    EXPECT_NE(refusal([&] { decode_welcome(j, "peer"); }).find("peer: kind: expected kind 2, got 1"), std::string::npos);
    std::vector<unsigned char> bad = j;
    bad[0] = 'X';
    EXPECT_NE(refusal([&] { shared_kind(bad, "peer"); }).find("not a tridex shared session message"), std::string::npos);
    EXPECT_NE(refusal([&] { decode_join(encode_join({kSharedProtocol, "B\no", Vec3(0.5)}), "peer"); }).find("control character"),
              std::string::npos);
    EXPECT_NE(refusal([&] { decode_join(encode_join({kSharedProtocol, "", Vec3(0.5)}), "peer"); }).find("peer: name"),
              std::string::npos);
    EXPECT_NE(refusal([&] { decode_join(encode_join({kSharedProtocol, "Bo", Vec3(2.0)}), "peer"); }).find("peer: colour"),
              std::string::npos);
    EXPECT_NE(refusal([&] {
                  decode_presence(encode_presence(tool_presence(kMaxSites, false, "x", Vec3(0.5), Pose{}, 0.0)), "peer");
              })
                  .find("peer: site: site 16"),
              std::string::npos);
    // Packed records that hold packed records, or lie about their size.
    std::vector<unsigned char> packed = encode_records(some_records(400));
    std::vector<unsigned char> nested = {'T', 'D', 'X', 'S', 9};
    const std::vector<unsigned char> frame = compute::pack_bytes(packed);
    nested.insert(nested.end(), frame.begin(), frame.end());
    EXPECT_NE(refusal([&] { decode_records(nested, "peer"); }).find("packed records hold packed records"), std::string::npos);
    std::vector<unsigned char> torn(packed.begin(), packed.end() - 10);
    EXPECT_NE(refusal([&] { decode_records(torn, "peer"); }).find("peer: packed records"), std::string::npos);
    std::vector<unsigned char> junk = {'T', 'D', 'X', 'S', 9, 1, 2, 3, 4};
    EXPECT_NE(refusal([&] { decode_records(junk, "peer"); }).find("not a zstd frame"), std::string::npos);
}

TEST(PresenceView, AnotherSitesToolIsABallAndItsNameAndAGoneSiteIsNotDrawn) {
    PresenceView view;
    std::vector<PresenceMessage> others(2);
    others[0] = tool_presence(1, false, "Bo", Vec3(0.5, 0.2, 0.9), Pose{Vec3(0.01, 0.02, 0.03), Quat(1, 0, 0, 0)}, 0.004);
    others[1] = tool_presence(2, true, "Cy", Vec3(0.5), Pose{}, 0.004);
    std::vector<renderer::SceneObject> out;
    view.append(others, out);
    ASSERT_EQ(out.size(), 2u);  // Bo's ball and name; Cy left
    EXPECT_FLOAT_EQ(out[0].world_from_model[3][0], 0.01f);
    EXPECT_FLOAT_EQ(out[0].world_from_model[0][0], 0.004f);  // the unit ball scaled to the tool's radius
    ASSERT_NE(out[1].mesh, nullptr);
    EXPECT_FALSE(out[1].mesh->triangles.empty());
    EXPECT_GT(out[1].world_from_model[3][1], 0.02f + 0.004f);  // above the ball
    const TriMesh* bo = out[1].mesh;
    out.clear();
    view.append(others, out);
    EXPECT_EQ(out[1].mesh, bo);  // the name's mesh is kept, not rebuilt each frame
}

TEST(PresenceView, ATrackedHeadTravelsInTheSceneFrameAndIsDrawnWithItsNameAndGlasses) {
    // Ann's scene is moved 1 m along -z and scaled up twice: her head 0.5 m in front of the screen in her room is
    // 0.75 m in front of the workpiece in the scene, and a real head's size is halved there.
    renderer::SceneNavigation nav(Pose{Vec3(0.0, 0.0, -1.0), Quat(1, 0, 0, 0)}, 2.0);
    FrameShown shown;
    shown.nav = &nav;
    shown.head = Pose{Vec3(0.0, 0.2, 0.5), Quat(1, 0, 0, 0)};
    shown.tool = ToolShape{};
    shown.tool.radius_m = 0.004;
    const PresenceMessage untracked = presence_of(shown, 0, "Ann", Vec3(0.2, 0.6, 1.0));
    EXPECT_FALSE(untracked.head_tracked);  // a fixed head is not shown
    shown.head_tracked = true;
    const PresenceMessage me = decode_presence(encode_presence(presence_of(shown, 0, "Ann", Vec3(0.2, 0.6, 1.0))), "t");
    ASSERT_TRUE(me.head_tracked);
    EXPECT_NEAR(me.head.position.z, 0.75, 1e-12);
    EXPECT_NEAR(me.head.position.y, 0.1, 1e-12);
    EXPECT_NEAR(me.head_size_m, kHeadRadiusM / 2.0, 1e-12);

    PresenceView view;
    std::vector<renderer::SceneObject> out;
    view.append({me}, out);
    ASSERT_EQ(out.size(), 5u);  // the tool's ball and name, the head, its glasses, its name
    EXPECT_FLOAT_EQ(out[2].world_from_model[3][2], 0.75f);
    EXPECT_NEAR(out[2].world_from_model[1][1], kHeadRadiusM / 2.0, 1e-6);  // the head as big as a head, in the scene
    EXPECT_LT(out[3].world_from_model[3][2], 0.75f);  // the glasses in front of it (-z looks ahead)
    EXPECT_LT(out[3].colour.r, 0.1f);
    EXPECT_EQ(out[4].mesh, out[1].mesh);  // one name mesh, drawn at the tool and, larger, above the head
    EXPECT_GT(out[4].world_from_model[3][1], 0.1f + kHeadRadiusM / 2.0);
    EXPECT_GT(out[4].world_from_model[0][0], 1.0f);

    // Names turn about the vertical to face the viewer: an eye off to the right turns them towards +x.
    out.clear();
    view.append({me}, out, Vec3(1.0, 0.1, 0.75));
    ASSERT_EQ(out.size(), 5u);
    EXPECT_GT(out[4].world_from_model[2][0], 0.99f);  // the text's front (+z) now points along +x
    EXPECT_NEAR(out[2].world_from_model[3][2], 0.75f, 1e-6);  // the head itself does not turn with the viewer

    PresenceMessage bad = me;
    bad.head_size_m = 0.0;
    EXPECT_NE(refusal([&] { decode_presence(encode_presence(bad), "peer"); }).find("peer: head_size_m"), std::string::npos);
}

}  // namespace
}  // namespace tridex::app
