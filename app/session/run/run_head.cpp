// app/session/run/run_head.cpp - the head-pose provider of a run.
#include "app/session/run/run_head.hpp"

namespace tridex::app {

std::unique_ptr<renderer::HeadPoseProvider> make_run_head(const RunScene& s, bool interactive,
                                                         renderer::KeyboardMouseHead** km, renderer::TrackerHead** tracker,
                                                         DTrackHead** dtrack) {
    *km = nullptr;
    *tracker = nullptr;
    *dtrack = nullptr;
    switch (s.head) {
        case HeadMode::kDTrack: {
            DTrackHeadSettings ds;
            ds.port = s.dtrack_port;
            ds.body = s.dtrack_body;
            ds.bind_address = s.dtrack_bind;
            ds.tracker_to_wall = s.display.tracker_to_wall;
            ds.head_to_eyes = s.display.head_to_eyes;
            ds.fallback = s.head_pose;
            ds.timeout_s = s.tracker_timeout_s;
            auto d = std::make_unique<DTrackHead>(ds);
            *dtrack = d.get();
            return d;
        }
        case HeadMode::kScripted:
            return std::make_unique<renderer::ScriptedHead>(s.head_waypoints, s.head_loop);
        case HeadMode::kTracker: {
            auto t = std::make_unique<renderer::TrackerHead>(s.head_pose, s.tracker_timeout_s);
            *tracker = t.get();
            return t;
        }
        case HeadMode::kFixed:
            break;
    }
    if (interactive) {
        auto k = std::make_unique<renderer::KeyboardMouseHead>(s.head_pose);
        *km = k.get();
        return k;
    }
    return std::make_unique<renderer::FixedHead>(s.head_pose);
}

}  // namespace tridex::app
