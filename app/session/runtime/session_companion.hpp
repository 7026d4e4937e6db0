// app/session/runtime/session_companion.hpp - a part that runs beside a run session's frames without being one of its
// sinks: it is told when the threads start, sees each frame just before it is presented, and is told when the
// threads stop. A cluster's rank 0 (app/session/cluster/cluster_root.hpp) is one: it drives the render ranks.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/menu/menu_frame.hpp"
#include "app/session/runtime/session_runtime.hpp"
#include "app/session/runtime/site_presence.hpp"
#include "core/error.hpp"
#include "core/pose.hpp"
#include "core/tool_shape.hpp"
#include "renderer/camera/scene_navigation.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

/// What one frame of a run session shows, as its companions see it just before it is presented.
struct FrameShown {
    std::uint64_t frame = 0;        ///< 0, 1, 2, ...
    Pose head;                      ///< the head pose it is drawn from (world m, before navigation: `nav` maps the
                                    ///< scene into this frame; the last good one when held)
    const renderer::SceneNavigation* nav = nullptr;  ///< the scene's navigation (world_from_scene)
    double eye_separation_m = 0.0;  ///< m
    Vec3 tool_m{0.0};               ///< tool centre, scene m (the haptic loop's world, which navigation leaves be)
    Quat tool_orientation{1.0, 0.0, 0.0, 0.0};
    ToolShape tool;                 ///< the tool drawn
    bool show_tool = true;          ///< whether the tool is drawn
    double ao = 1.0;                ///< ambient occlusion strength, 0..1
    const MenuFrame* menu = nullptr;  ///< the pie menu as drawn (scene m); null or not shown: none
    /// Where the tool rests on the surface, scene m: contact point 0's proxy (god-object), the tool centre when free.
    Vec3 proxy_m{0.0};
    /// The workpiece's pose as drawn (its model frame -> the scene): the scene's, or where the tool placed it.
    Pose workpiece_pose{};
    /// The head follows a tracker or a script (not a fixed head, nor one the keyboard and mouse move): a shared
    /// session shows it to the others.
    bool head_tracked = false;
    /// The other sites the companions know of (a shared session's people: SessionCompanion::add_presence), as this
    /// site draws them; a cluster wall's render ranks draw them too.
    std::vector<SitePresence> others{};
};

/// What RunPipeline::run throws after a companion failed (once every output is written): the companion's failure and
/// what the session kept. `tridex run` exits with 5 for it.
class CompanionError : public Error {
public:
    explicit CompanionError(const std::string& message) : Error(message) {}
};

/// A companion of RunPipeline. Every call is on the frame loop's thread. A companion that fails says so through
/// failure(): the session then ends as if its window had closed, keeps and writes all its work (journal, model,
/// report), and the run ends with that failure as its error.
class SessionCompanion {
public:
    virtual ~SessionCompanion() = default;
    /// Before the session's threads are made: what the sculpt thread should also do (SculptOptions::stream).
    virtual void configure(SculptOptions& options) { (void)options; }
    /// The threads are made and not started: the workpiece is as loaded (`runtime.workpiece()` may be read).
    virtual void starting(SessionRuntime& runtime) { (void)runtime; }
    /// Just before frame `shown.frame` is presented.
    virtual void before_present(const FrameShown& shown) { (void)shown; }
    /// After the threads stopped (the model is final and may be read), before the outputs are written; `last`
    /// is the last frame as shown (frame number one past the last presented).
    virtual void stopped(SessionRuntime& runtime, const FrameShown& last) { (void)runtime, (void)last; }
    /// Appends the other sites it knows of (a shared session's people, gone ones left out), for FrameShown::others.
    /// Called on the frame loop's thread, once a frame, before before_present().
    virtual void add_presence(std::vector<SitePresence>& out) const { (void)out; }
    /// Why the companion cannot go on; "" while it can.
    virtual std::string failure() const { return ""; }
    /// Why the session ends now, normally (a shared session's host ended it); "" while it goes on. Asked once a frame.
    virtual std::string ended() const { return ""; }
    /// True while an offscreen session must go on past the end of its own stroke or scripted cursor and past the
    /// offscreen safety net (a joiner of a shared session stays until the host ends it or goes away). --frames and
    /// --seconds still end it.
    virtual bool holds_session_open() const { return false; }
    /// Its part of report.json (under its own key), or null.
    virtual nlohmann::json report() const { return nullptr; }
    /// The key of report() in report.json.
    virtual std::string report_key() const = 0;
};

}  // namespace tridex::app
