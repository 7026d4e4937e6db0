// tests/app/cluster_replica_helpers.hpp - what the render-rank replica tests share: the bunny's spec, the wall and its
// frames, and the contour check.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "app/scene/run_scene.hpp"
#include "app/scene/session_spec.hpp"
#include "app/session/cluster/cluster_replica.hpp"
#include "app/support/assets.hpp"

namespace tridex::app::test {

/// The session spec of the default scene's bunny at `resolution` cells, as rank 0's hello carries it.
inline std::string bunny_spec_json(int resolution) {
    SessionSpec spec = RunScene::default_spec();
    spec.mesh_path = default_mesh_path();
    spec.resolution = resolution;
    return spec_to_json(spec);
}

/// A frame that shows the bunny `scale` times its size on the wall, seen from 3 m, without the tool.
inline FrameMessage wall_frame(double scale) {
    FrameMessage m;
    m.head = Pose{Vec3(0.0, 1.74, 3.0), Quat(1.0, 0.0, 0.0, 0.0)};
    m.nav_pose = Pose{Vec3(0.0, 1.74, 0.0), Quat(1.0, 0.0, 0.0, 0.0)};
    m.nav_scale = scale;
    m.show_tool = false;
    return m;
}

/// The 3.05 m wall as one 320x240 viewport.
inline ClusterViewport small_wall() {
    ClusterViewport wall;
    wall.name = "wall";
    wall.screen = renderer::Screen{Vec3(-1.524, 0.60, 0.0), Vec3(1.524, 0.60, 0.0), Vec3(-1.524, 2.886, 0.0)};
    wall.width_px = 320;
    wall.height_px = 240;
    return wall;
}

/// The two replicas' contours are the same, bit for bit.
inline void expect_same_contour(const ClusterReplica& a, const ClusterReplica& b) {
    const TriMesh ma = a.contourer().mesh(), mb = b.contourer().mesh();
    EXPECT_EQ(ma.positions, mb.positions);
    EXPECT_EQ(ma.triangles, mb.triangles);
}

}  // namespace tridex::app::test
