// renderer/output/stereo_sink.cpp - the eye policy shared by every sink: how many eyes a frame draws.
#include "renderer/output/stereo_sink.hpp"

namespace tridex::renderer {

FrameStats StereoSink::draw(OffscreenStereoRenderer& renderer, const SceneView& scene, const StereoCamera& camera) {
    SceneView view = scene;
    view.eye_count = eye_count();
    const double separation_m = view.eye_count == 2 ? camera.eye_separation_m : 0.0;
    return renderer.draw(view, camera.screen, camera.head, separation_m, camera.near_m, camera.far_m);
}

}  // namespace tridex::renderer
