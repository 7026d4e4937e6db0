// A shared session's host and joiner in one process over the link shim (one-way latency and loss), each with its own
// sculpt thread: the joiner's replica ends equal to the host's model, its own groove carved through the host, its
// undo taken back through the host and refused while the host's stroke is newer; a joiner whose link is cut goes
// away cleanly and the host carries on. No run session and no GPU: these run under ThreadSanitizer too (the host's and
// the joiner's network threads beside the sculpt threads).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include "app/session/shared/shared_host.hpp"
#include "app/session/shared/shared_join.hpp"
#include "app/support/file_bytes.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"
#include "devices/net/link_shim.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
namespace net = devices::net;
using Clock = std::chrono::steady_clock;

compute::TriDexel box_model() {
    compute::TriDexel m =
        compute::TriDexel::empty(compute::Lattice::around(Aabb{Vec3(-0.05), Vec3(0.05)}, 40), std::size_t(1) << 30);
    compute::scan_convert(box_mesh(Aabb{Vec3(-0.0487), Vec3(0.0487)}), m);
    return m;
}

std::vector<ToolSample> groove(double y_m, double x0_m, double x1_m, int n, double t0_s) {
    std::vector<ToolSample> s(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) {
        ToolSample& x = s[static_cast<std::size_t>(i)];
        x.t_s = t0_s + i * 1e-3;
        x.position = Vec3(x0_m + (x1_m - x0_m) * std::min(i, n - 1) / (n - 1), y_m, 0.046);
        x.tool.radius_m = 0.005;
        x.op = i < n ? ToolOp::kSubtract : ToolOp::kNone;
    }
    return s;
}

net::SessionKey key_of(std::uint8_t seed) {
    std::uint8_t b[net::SessionKey::kBytes];
    for (std::size_t i = 0; i < sizeof b; ++i) b[i] = static_cast<std::uint8_t>(seed + 13 * i);
    return net::SessionKey(b);
}

// A site's model, contour and sculpt thread, wired as a companion's configure() asks.
struct Site {
    explicit Site(compute::TriDexel m) : model(std::move(m)), contourer(model) {
        contourer.update(model);
        thread = std::make_unique<SculptThread>(model, contourer, ring, surface, Vec3(0.0));
    }
    void wire(const SculptOptions& o) {
        for (compute::ToolStreamSink* s : o.streams) thread->use_stream(*s);
        for (const auto& f : o.sculpt_setup) f(*thread);
    }
    void push(const std::vector<ToolSample>& s) {
        for (const ToolSample& x : s)
            while (!ring.try_push(x)) std::this_thread::yield();
    }
    compute::TriDexel model;
    compute::Contourer contourer;
    SpscRing<ToolSample> ring{4096};
    TripleBuffer<ActiveSurface> surface;
    std::unique_ptr<SculptThread> thread;
};

// Starts `host` on `model` as a run session's host does: the model's .tdx bytes go to a joiner that asks for the start,
// the model as it stands (written the same way) to one that joins late.
void start_host(SharedHost& host, const compute::TriDexel& model, const fs::path& dir);

// Wires a site's sculpt thread as the host's (its stream, intake and snapshots) and starts the host on its model.
void host_site(SharedHost& host, Site& hs, const fs::path& dir) {
    SculptOptions o;
    host.configure(o);
    hs.wire(o);
    start_host(host, hs.model, dir);
}

// Wires a site's sculpt thread to follow the host `join` joined.
void join_site(SharedJoin& join, Site& js) {
    SculptOptions o;
    join.configure(o);
    js.wire(o);
}

void start_host(SharedHost& host, const compute::TriDexel& model, const fs::path& dir) {
    const std::string path = (dir / "shared_start.tdx").string();
    compute::save_tdx(path, model, Mat4(1.0), "{}");
    const std::string late = (dir / "shared_late_join.tdx").string();
    host.start(model, read_file_bytes(path), "{}", [late](const compute::TriDexel& m) {
        compute::save_tdx(late, m, Mat4(1.0), "{}");
        return read_file_bytes(late);
    });
}

// An empty folder in the test's temporary folder, with a `host` and a `join` folder in it.
fs::path fresh_sites_dir(const char* name) {
    const fs::path dir = fs::path(testing::TempDir()) / name;
    fs::remove_all(dir);
    fs::create_directories(dir / "host");
    fs::create_directories(dir / "join");
    return dir;
}

// Waits until `done` or 60 s; false on time-out.
template <class F>
bool wait_until(F done) {
    const auto end = Clock::now() + std::chrono::seconds(60);
    while (!done()) {
        if (Clock::now() > end) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
}

// The host ends the session and the joiner hears the end: both sculpt threads stopped, both sides finished.
void end_session(SharedHost& host, Site& hs, SharedJoin& join, Site& js) {
    hs.thread->stop();
    host.finish(hs.model);
    ASSERT_TRUE(wait_until([&] { return !join.ended().empty(); })) << join.failure();
    js.thread->stop();
    join.finish(js.model);
    EXPECT_EQ(join.failure(), "");
}

TEST(SharedLink, AJoinerOverALossyLinkEndsWithTheHostsModelAndUndoesThroughTheHost) {
    const fs::path dir = fresh_sites_dir("tridex_shared_link");
    const auto t0 = Clock::now();
    net::ShimConfig cfg;
    cfg.latency_s = 0.02;
    cfg.loss = 0.05;
    net::LinkShim shim(cfg, [t0] { return std::chrono::duration<double>(Clock::now() - t0).count(); });
    std::unique_ptr<net::DatagramLink> server_end = shim.server_end();

    SharedHostOptions ho;
    ho.key = key_of(3);
    ho.name = "Ann";
    ho.out = (dir / "host").string();
    ho.digest_check_s = 0.2;
    SharedHost host(ho, [&server_end]() { return std::move(server_end); });  // one peer, on the network thread
    Site hs(box_model());
    host_site(host, hs, dir / "host");
    hs.thread->start();

    SharedJoinOptions jo;
    jo.name = "Bo";
    jo.out = (dir / "join").string();
    SharedJoin join(jo, shim.client_end(), key_of(3));
    const SharedJoin::Joined joined = join.join();
    EXPECT_EQ(joined.welcome.site, 1);
    EXPECT_EQ(joined.welcome.host_name, "Ann");
    Site js(compute::load_tdx(joined.start_path, std::size_t{1} << 30).model);
    EXPECT_EQ(compute::model_digest(js.model), compute::model_digest(hs.model));
    join_site(join, js);
    js.thread->start();
    // Each site's frame loop: its own tool to the others, theirs read back, as a run session's frames do.
    std::atomic<bool> frames_stop{false};
    std::thread frames([&] {
        SitePresence ann, bo;
        ann.name = "Ann";
        ann.tool_radius_m = 0.005;
        bo.name = "Bo";
        bo.tool_radius_m = 0.005;
        bo.head_tracked = true;
        bo.head = Pose{Vec3(0.0, 0.3, 0.6), Quat(1, 0, 0, 0)};
        bo.head_size_m = kHeadRadiusM;
        while (!frames_stop.load()) {
            host.set_own_presence(ann);
            join.set_own_presence(bo);
            (void)host.others();
            (void)join.others();
            (void)host.joiners();
            (void)join.failure();
            (void)join.ended();
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    });

    hs.push(groove(0.02, -0.03, 0.03, 150, 0.0));  // the host's groove
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    js.push(groove(-0.02, 0.03, -0.03, 150, 0.0));  // then the joiner's: its stroke is the newest
    ASSERT_TRUE(wait_until([&] { return !host.joiners().empty() && host.joiners()[0].samples == 151; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const std::uint64_t steps = hs.thread->live().steps;
    ASSERT_TRUE(js.thread->request(SculptRequest::kUndo));  // the joiner's groove, taken back through the host
    ASSERT_TRUE(wait_until([&] { return hs.thread->live().steps > steps; }));
    hs.push(groove(0.0, -0.03, 0.03, 60, 5.0));  // the host carves again
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    ASSERT_TRUE(js.thread->request(SculptRequest::kRedo));  // the host's stroke is newer: nothing to redo (cleared)
    std::this_thread::sleep_for(std::chrono::milliseconds(400));

    // Each site heard the other's presence (unreliable: newest wins, some lost), the joiner's head with it.
    EXPECT_TRUE(wait_until([&] { return !host.others().empty() && !join.others().empty(); }));
    frames_stop.store(true);
    frames.join();
    ASSERT_EQ(host.others().size(), 1u);
    EXPECT_EQ(host.others()[0].name, "Bo");
    EXPECT_EQ(host.others()[0].site, 1);
    EXPECT_TRUE(host.others()[0].head_tracked);
    ASSERT_EQ(join.others().size(), 1u);
    EXPECT_EQ(join.others()[0].name, "Ann");
    EXPECT_EQ(join.others()[0].site, 0);

    ASSERT_NO_FATAL_FAILURE(end_session(host, hs, join, js));
    const nlohmann::json r = join.report();
    EXPECT_TRUE(r["digest_match"].get<bool>());
    EXPECT_GT(r["digest_checks"].get<std::uint64_t>(), 0u);
    EXPECT_EQ(compute::model_digest(js.model), compute::model_digest(hs.model));
    EXPECT_EQ(hs.thread->stats().history.undos, 1u);
    EXPECT_EQ(js.thread->stats().forwarded, 151u);
    const nlohmann::json h = host.report();
    EXPECT_EQ(h["joiners"][0]["requests"].get<std::uint64_t>(), 2u);
    EXPECT_GT(shim.stats().lost, 0u);  // the link lost datagrams (unreliable presence), the stream none
}

TEST(SharedLink, ALateJoinerGetsTheModelAsItStandsAndFollowsTheHostsUndoOfAStrokeBeforeIt) {
    const fs::path dir = fresh_sites_dir("tridex_shared_link_late");
    const auto t0 = Clock::now();
    net::ShimConfig cfg;
    cfg.latency_s = 0.01;
    net::LinkShim shim(cfg, [t0] { return std::chrono::duration<double>(Clock::now() - t0).count(); });
    std::unique_ptr<net::DatagramLink> server_end = shim.server_end();
    SharedHostOptions ho;
    ho.key = key_of(5);
    ho.out = (dir / "host").string();
    ho.digest_check_s = 0.2;
    SharedHost host(ho, [&server_end]() { return std::move(server_end); });
    Site hs(box_model());
    host_site(host, hs, dir / "host");
    hs.thread->start();
    hs.push(groove(0.02, -0.03, 0.03, 150, 0.0));  // carved before anyone joins
    ASSERT_TRUE(wait_until([&] { return hs.thread->live().steps > 0 && hs.ring.size() == 0; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));

    SharedJoinOptions jo;
    jo.name = "Bo";
    jo.out = (dir / "join").string();
    SharedJoin join(jo, shim.client_end(), key_of(5));
    const SharedJoin::Joined joined = join.join();
    EXPECT_GT(joined.welcome.first_record, 0u);  // the model as it stands: the groove is in it
    EXPECT_FALSE(joined.welcome.history.empty());
    Site js(compute::load_tdx(joined.start_path, std::size_t{1} << 30).model);
    EXPECT_EQ(compute::model_digest(js.model), joined.welcome.initial_digest);
    EXPECT_NE(joined.welcome.initial_digest, compute::model_digest(box_model()));
    join_site(join, js);
    js.thread->start();
    ASSERT_TRUE(hs.thread->request(SculptRequest::kUndo));  // the host takes back its stroke from before the join
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    js.push(groove(-0.02, 0.03, -0.03, 100, 0.0));  // and the joiner carves
    ASSERT_TRUE(wait_until([&] { return !host.joiners().empty() && host.joiners()[0].samples == 101; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(400));

    ASSERT_NO_FATAL_FAILURE(end_session(host, hs, join, js));
    EXPECT_TRUE(join.report()["digest_match"].get<bool>());
    EXPECT_EQ(compute::model_digest(js.model), compute::model_digest(hs.model));
    EXPECT_EQ(hs.thread->stats().history.undos, 1u);
    EXPECT_EQ(js.thread->stats().undo_ms.size(), 1u);  // followed from the history the welcome carried
    EXPECT_GT(host.report()["joiners"][0]["first_record"].get<std::uint64_t>(), 0u);
}

TEST(SharedLink, AJoinerWithAnotherKeyNeverJoinsAndTheHostCountsIt) {
    const fs::path dir = fs::path(testing::TempDir()) / "tridex_shared_link_key";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto t0 = Clock::now();
    net::LinkShim shim(net::ShimConfig{}, [t0] { return std::chrono::duration<double>(Clock::now() - t0).count(); });
    std::unique_ptr<net::DatagramLink> server_end = shim.server_end();
    SharedHostOptions ho;
    ho.key = key_of(3);
    ho.out = dir.string();
    SharedHost host(ho, [&server_end]() { return std::move(server_end); });
    Site hs(box_model());
    host_site(host, hs, dir);
    SharedJoinOptions jo;
    jo.out = dir.string();
    jo.join_timeout_s = 5.0;
    SharedJoin join(jo, shim.client_end(), key_of(4));
    try {
        join.join();
        ADD_FAILURE() << "a joiner with another key joined";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("handshake"), std::string::npos) << e.what();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the host reads the stranger's hello too
    host.finish(hs.model);
    EXPECT_EQ(host.report()["peers_refused"].get<std::uint64_t>(), 1u);
}

}  // namespace
}  // namespace tridex::app
