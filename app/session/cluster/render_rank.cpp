// app/session/cluster/render_rank.cpp - a render rank's loop: frame messages in, viewports drawn, the swap barrier.
#include "app/session/cluster/render_rank.hpp"

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/session/cluster/cluster_replica.hpp"
#include "renderer/stereo/frame_eyes.hpp"
#include "app/session/cluster/frame_message.hpp"
#include "app/session/view/presence_view.hpp"
#include "app/session/report/session_report.hpp"
#include "app/support/file_bytes.hpp"
#include "compute/model/model_digest.hpp"
#include "core/duration_histogram.hpp"
#include "core/error.hpp"
#include "core/format.hpp"
#include "gpu/context.hpp"
#include "renderer/output/offscreen_sink.hpp"
#include "renderer/output/stereo_output.hpp"
#include "renderer/window/window_glfw.hpp"
#include "renderer/window/window_sink.hpp"

namespace tridex::app {

namespace {

using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

double now_s() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// One viewport: its window (if shown), renderer and sink.
struct Viewport {
    const ClusterViewport* config = nullptr;
    std::optional<renderer::Window> window;
    std::optional<renderer::OffscreenStereoRenderer> rend;
    std::unique_ptr<renderer::StereoSink> sink;
};

// A fault injected by the tests (docs/cluster.md, "Faults"): TRIDEX_CLUSTER_FAULT=RANK:FRAME:exit|kill|hang|diverge
// makes render rank RANK exit with code 9, die of SIGKILL, stop answering, or change its model by one float step, when
// frame FRAME (or the last frame, if sooner) arrives.
struct Fault {
    int rank = -1;
    std::uint64_t frame = 0;
    std::string kind;
};

Fault fault_from_env() {
    Fault f;
    const char* v = std::getenv("TRIDEX_CLUSTER_FAULT");
    if (!v) return f;
    int rank = -1;
    unsigned long long frame = 0;
    char kind[8] = {};
    if (std::sscanf(v, "%d:%llu:%7s", &rank, &frame, kind) == 3) {
        f.rank = rank;
        f.frame = frame;
        f.kind = kind;
    }
    return f;
}

// What the last frame showed, so that it can be drawn again elsewhere (the tests' one-machine reference).
nlohmann::json last_frame_json(const FrameMessage& m) {
    const auto v3 = [](const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    const auto q4 = [](const Quat& q) { return nlohmann::json::array({q.w, q.x, q.y, q.z}); };
    return {{"frame", m.frame},
            {"head_m", v3(m.head.position)},
            {"head_orientation", q4(m.head.orientation)},
            {"nav_m", v3(m.nav_pose.position)},
            {"nav_orientation", q4(m.nav_pose.orientation)},
            {"nav_scale", m.nav_scale},
            {"eye_separation_m", m.eye_separation_m},
            {"show_tool", m.show_tool},
            {"tool_m", v3(m.tool_m)},
            {"tool_orientation", q4(m.tool_orientation)},
            {"tool_radius_m", m.tool.radius_m},
            {"tool_length_m", m.tool.length_m},
            {"tool_kind", static_cast<int>(m.tool.kind)},
            {"ao", m.ao}};
}

class RenderRank {
public:
    RenderRank(ClusterTransport& t, const ClusterConfig& c, const RenderRankOptions& o)
        : t_(t), c_(c), o_(o), mine_(c.find(t.rank())), fault_(fault_from_env()) {}

    int run() {
        std::uint64_t frame = 0;
        try {
            if (!mine_) throw Error(c_.source + ": names no viewports for rank " + std::to_string(t_.rank()));
            open();
            for (bool last = false; !last;) last = one_frame(frame);
            finish(frame);
            (void)t_.flush(deadline_after(c_.timeout_s));
            return 0;
        } catch (const std::exception& e) {
            const std::string why = e.what();
            std::fprintf(stderr, "tridex: cluster render rank %d: %s\n", t_.rank(), why.c_str());
            try {
                RankAnswer a;
                a.frame = frame;
                a.error = why;
                t_.send(0, encode_answer(a));
                (void)t_.flush(deadline_after(2.0));
            } catch (const std::exception&) {  // rank 0 may be gone: the error is said above
            }
            return 5;
        }
    }

private:
    std::vector<unsigned char> wait_for_rank0(double timeout_s, const char* what) {
        auto got = t_.receive(0, deadline_after(timeout_s));
        if (!got)
            throw Error("rank 0 sent no " + std::string(what) + " within " + format_number(timeout_s) +
                        " s (it ended, hangs or is unreachable)");
        if (const std::optional<std::string> why = let_go_reason(*got))
            throw Error("rank 0 let this render rank go " + *why + " (a new process may take its place)");
        return std::move(*got);
    }

    void open() {
        const HelloMessage hello = decode_hello(wait_for_rank0(c_.start_timeout_s, "session"), "rank 0's hello");
        const auto t0 = Clock::now();
        std::string spec_json = hello.spec_json;
        if (!hello.model_tdx.empty()) {
            // The model rank 0 started from, as bytes: its path may exist on rank 0's machine only.
            const fs::path start = fs::path(o_.out) / ("cluster_start_rank" + std::to_string(t_.rank()) + ".tdx");
            fs::create_directories(start.parent_path());
            write_file_bytes(start.string(), hello.model_tdx);
            SessionSpec spec = spec_from_json(spec_json, "rank 0's hello");
            spec.model_path = start.string();
            spec_json = spec_to_json(spec);
        }
        const bool late = hello.first_record > 0 || !hello.history.empty();  // it joined a running wall
        replica_.emplace(spec_json, lod_choice(c_.lod), late ? &hello : nullptr,
                         ReplicaContour{c_.startup == "coarse", c_.stroke_contour == "coarse"});
        first_record_ = hello.first_record;
        palette_ = spec_from_json(hello.spec_json, "rank 0's hello").palette;  // the session's names and colours
        menu_root_ = default_menu(palette_);
        load_ms_ = ms_since(t0);
        if (replica_->digest() != hello.initial_digest)
            throw Error("the workpiece built here differs from rank 0's (digest " + compute::digest_hex(replica_->digest()) +
                        ", rank 0's " + compute::digest_hex(hello.initial_digest) +
                        "): another mesh file or build on this machine");
        bool windows = false;
        for (const ClusterViewport& v : mine_->viewports) windows |= v.output != ViewportOutput::kOffscreen;
        if (windows) glfw_.emplace();
        gpu::ContextOptions gopt;
        gopt.validation = o_.validate;
        ctx_.emplace(gpu::Context::create(windows ? renderer::window_context_options(gopt) : gopt));
        for (const ClusterViewport& v : mine_->viewports) {
            // Made in place and never moved: the sink holds the window by reference.
            Viewport& vp = *viewports_.emplace_back(std::make_unique<Viewport>());
            vp.config = &v;
            const renderer::SinkOptions so{v.stereo, v.swap_eyes, v.anaglyph, v.refresh_hz};
            if (v.output == ViewportOutput::kOffscreen) {
                vp.sink = std::make_unique<renderer::OffscreenSink>(*ctx_, so);
            } else {
                renderer::WindowOptions wo;
                wo.title = "tridex wall - rank " + std::to_string(t_.rank()) + " - " + v.name;
                std::tie(wo.width, wo.height) = renderer::output_size(v.stereo, v.width_px, v.height_px);
                wo.fullscreen = v.output == ViewportOutput::kFullscreen;
                wo.monitor_index = wo.fullscreen ? v.monitor : -1;
                wo.resizable = false;
                vp.window.emplace(renderer::Window::create(wo));
                vp.sink = renderer::WindowSink::create(*ctx_, *vp.window, so);
            }
            vp.rend.emplace(renderer::OffscreenStereoRenderer::create(*ctx_, v.width_px, v.height_px));
        }
        RankAnswer ready;
        ready.frame = kHelloAnswerFrame;
        t_.send(0, encode_answer(ready));
    }

    // One frame; true when it was the last.
    bool one_frame(std::uint64_t& frame) {
        const FrameMessage m = decode_frame(wait_for_rank0(frame == 0 ? c_.start_timeout_s : c_.timeout_s, "frame"),
                                            "rank 0's frame " + std::to_string(frame));
        frame = m.frame;
        last_ = m;
        last_.records.clear();
        if (t_.rank() == fault_.rank && (m.frame >= fault_.frame || m.last)) {
            if (fault_.kind == "exit") std::_Exit(9);
            if (fault_.kind == "kill") ::raise(SIGKILL);
            if (fault_.kind == "hang")
                for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
            if (fault_.kind == "diverge" && !diverged_) {
                replica_->diverge();
                diverged_ = true;
            }
        }
        RankAnswer a;
        a.frame = m.frame;
        a.previous_present_s = last_present_s_;
        auto t0 = Clock::now();
        if (const std::optional<std::uint64_t> mismatch = replica_->apply(m)) {
            a.digest_mismatch = true;
            a.digest = *mismatch;
            t_.send(0, encode_answer(a));
            throw Error("the model here differs from rank 0's at frame " + std::to_string(m.frame) + " (digest check)");
        }
        if (m.check_digest) ++checks_;
        a.apply_ms = ms_since(t0);
        apply_ms_.add(a.apply_ms);
        t0 = Clock::now();
        // Only the tiles this rank's viewports can see (and their neighbours) are contoured; the rest wait.
        frusta_.clear();
        for (const std::unique_ptr<Viewport>& vp : viewports_) {
            const renderer::StereoCamera c = ClusterReplica::camera(*vp->config, m);
            const renderer::FrameEyes eyes = renderer::frame_eyes(renderer::SceneView{}, c.screen, c.head, c.eye_separation_m,
                                                                  c.near_m, c.far_m, vp->config->width_px, vp->config->height_px);
            frusta_.push_back(eyes.frusta[0]);
            if (c.eye_separation_m > 0.0) frusta_.push_back(eyes.frusta[1]);
        }
        replica_->contour(frusta_);
        contour_ms_.add(ms_since(t0));
        renderer::SceneView view = replica_->view(m);
        view.palette = &palette_;
        // Rank 0's pie menu, drawn here the same (both eyes, at the hand's depth in the scene).
        menu_objects_.assign(view.objects.begin(), view.objects.end());  // the reference objects first
        menu_drawing_.append(m.menu, menu_root_, menu_objects_);
        if (!m.others.empty()) {  // a shared session's other people, drawn as rank 0 draws them, names facing the head
            const Vec3 eye = viewports_.empty() ? Vec3(std::numeric_limits<double>::quiet_NaN())
                                                : ClusterReplica::camera(*viewports_.front()->config, m).head.position;
            presence_view_.append(m.others, menu_objects_, eye, m.workpiece_pose);
        }
        others_ = m.others.size();
        view.objects = menu_objects_;
        for (const std::unique_ptr<Viewport>& vp : viewports_) {
            if (vp->window) vp->window->poll_events();
            vp->sink->draw(*vp->rend, view, ClusterReplica::camera(*vp->config, m));
        }
        // A coarse-first start-up and a stroke drawn coarse are refined next where these frames drew a group over its
        // pixel bound; a stroke leaves the levels under those they drew within it for later.
        for (const std::unique_ptr<Viewport>& vp : viewports_) {
            const renderer::FrameStats& stats = vp->rend->last_frame_stats();
            replica_->want_detail(stats.groups_wanting_detail);
            replica_->frames_drew(stats.groups_at_level);
        }
        a.draw_ms = ms_since(t0);
        if (frames_ == 0) first_frame_ms_ = load_ms_ + a.draw_ms;
        draw_ms_.add(a.draw_ms);
        t_.send(0, encode_answer(a));
        const std::uint64_t go = decode_go(wait_for_rank0(c_.timeout_s, "go"), "rank 0's go");
        if (go != m.frame) throw Error("rank 0 released frame " + std::to_string(go) + " while frame " + std::to_string(m.frame) + " waited");
        for (const std::unique_ptr<Viewport>& vp : viewports_) presents_ += static_cast<std::uint64_t>(vp->sink->present(*vp->rend));
        last_present_s_ = now_s();
        ++frames_;
        return m.last;
    }

    void finish(std::uint64_t frame) {
        nlohmann::json files = nlohmann::json::array();
        for (const std::unique_ptr<Viewport>& vp : viewports_) {
            vp->rend->finish();
            if (vp->config->output != ViewportOutput::kOffscreen) continue;
            const fs::path dir = fs::path(o_.out) / vp->config->name;
            fs::create_directories(dir);
            for (const std::string& f : vp->sink->finish(*vp->rend, dir.string())) files.push_back(f);
        }
        RankAnswer done;
        done.kind = ClusterKind::kDone;
        done.frame = frame;
        done.previous_present_s = last_present_s_;
        done.digest = replica_->digest();
        std::uint64_t triangles = 0;  // the last frame's workpiece triangles, every viewport's eyes
        for (const std::unique_ptr<Viewport>& vp : viewports_)
            for (const std::size_t n : vp->rend->last_frame_stats().tile_triangles) triangles += n;
        const nlohmann::json report = {{"rank", t_.rank()},
                                       {"frames", frames_},
                                       {"presents", presents_},
                                       {"checks", checks_},
                                       {"workpiece_load_ms", load_ms_},
                                       {"first_record", first_record_},
                                       {"records", replica_->applied().records},
                                       {"samples", replica_->applied().samples},
                                       {"final_digest", done.digest},
                                       {"apply_ms", summary_report_json(apply_ms_)},
                                       {"contour_ms", summary_report_json(contour_ms_)},
                                       {"tiles_contoured", replica_->tiles_contoured()},
                                       {"tiles_deferred_at_end", replica_->tiles_deferred()},
                                       {"other_sites_last_frame", others_},
                                       {"lod", c_.lod},
                                       {"lod_pending_at_end", replica_->lod_pending()},
                                       {"startup", replica_->started_coarse() ? "coarse" : "full"},
                                       {"startup_tiles_refined", replica_->startup_tiles_refined()},
                                       {"startup_pending_at_end", replica_->startup_pending()},
                                       {"first_frame_ms", first_frame_ms_},
                                       {"stroke_contour", replica_->strokes_coarse() ? "coarse" : "full"},
                                       {"stroke_tiles_deferred", replica_->stroke_tiles_deferred()},
                                       {"stroke_tiles_contoured", replica_->stroke_tiles_contoured()},
                                       {"stroke_tiles_waiting_at_end", replica_->stroke_tiles_waiting()},
                                       {"tile_triangles_last_frame", triangles},
                                       {"draw_ms", summary_report_json(draw_ms_)},
                                       {"validation_messages", ctx_->validation_messages()},
                                       {"last_frame", last_frame_json(last_)},
                                       {"files", files}};
        done.report_json = report.dump();
        t_.send(0, encode_answer(done));
    }

    ClusterTransport& t_;
    const ClusterConfig& c_;
    const RenderRankOptions& o_;
    const ClusterRank* mine_;
    Fault fault_;
    std::optional<ClusterReplica> replica_;
    std::vector<renderer::Frustum> frusta_;  // this frame's, one or two per viewport
    MaterialPalette palette_ = default_material_palette();  // the session's materials (rank 0's spec)
    MenuItem menu_root_ = default_menu();               // the menu whose rings rank 0's frames name
    MenuDrawing menu_drawing_;                          // its meshes, rebuilt when rank 0's menu changes
    std::vector<renderer::SceneObject> menu_objects_;   // the view's objects: the references, the menu, the other sites'
    PresenceView presence_view_;                        // a shared session's other sites (their meshes kept here)
    std::size_t others_ = 0;                            // other sites in the last frame drawn
    FrameMessage last_;  // the last frame message (without its records): its view, for the report
    std::optional<renderer::WindowSystemScope> glfw_;
    std::optional<gpu::Context> ctx_;
    std::vector<std::unique_ptr<Viewport>> viewports_;  // after ctx_: destroyed before it
    double last_present_s_ = 0.0, load_ms_ = 0.0;
    double first_frame_ms_ = 0.0;     // the replica built, then the first frame contoured and drawn (no waits), ms
    std::uint64_t first_record_ = 0;  // the stream's record this rank started from (> 0: it joined a running wall)
    std::uint64_t frames_ = 0, presents_ = 0, checks_ = 0;
    bool diverged_ = false;  // the diverge fault was injected
    // Per frame, ms; fixed bins, so a wall session of any length keeps the same memory.
    DurationHistogram apply_ms_ = DurationHistogram::fine(), contour_ms_ = DurationHistogram::fine(),
                      draw_ms_ = DurationHistogram::fine();
};

}  // namespace

int run_render_rank(ClusterTransport& transport, const ClusterConfig& config, const RenderRankOptions& options) {
    return RenderRank(transport, config, options).run();
}

}  // namespace tridex::app
