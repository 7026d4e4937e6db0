// bench/bench_wall.hpp - the stiff wall the link and filter benchmarks press the simulated hand into.
#pragma once

#include <memory>

#include "core/active_surface.hpp"
#include "devices/scripted_path.hpp"

namespace tridex::bench {

/// The half-space z < 0 (world m) as the Z rays see it: 1 mm cells, lattice origin (-16, -16, -20) mm, the window over
/// x, y in [-16, 15] mm, every ray solid from 20 mm below the wall up to z = 0. Sequence 1, centred on the origin.
std::unique_ptr<ActiveSurface> bench_wall_surface();

/// The hand's target (device frame = world here): 10 mm above the wall at t = 0, depth_m (m, > 0) into it at 0.3 s,
/// held there until 1.5 s (exactly still from 0.4 to 1.4 s), back to 10 mm above by 1.8 s, held to 2.5 s. The default
/// hand (300 N/m) settles where its spring balances the wall's: 300 * (depth - p) = K * p.
devices::ScriptedPath bench_wall_press(double depth_m);

}  // namespace tridex::bench
