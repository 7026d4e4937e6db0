// bench/bench_shared_sites.hpp - what `tridex bench --shared`'s runs share (internal to bench/): a site (model,
// contour, sculpt thread publishing per-tile meshes), the scripted groove a site carves, pushing samples at 1 kHz on
// the wall clock, the session's key and the starting box.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <thread>
#include <utility>
#include <vector>

#include "app/session/runtime/session_runtime.hpp"
#include "app/session/shared/shared_host.hpp"
#include "app/session/shared/shared_join.hpp"
#include "app/session/shared/shared_site.hpp"
#include "compute/model/tdx_file.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/primitives.hpp"
#include "devices/net/sealed_link.hpp"

namespace tridex::bench::shared_sites {

using Clock = std::chrono::steady_clock;

/// The steady clock's time, s (for push and publish times).
inline double now_s() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }

/// One site: its model, contour, sculpt thread publishing per-tile meshes (started by the caller after wire()), and
/// what its publishes carried. The sculpt thread takes its samples from `ring` and publishes `surface` (what a haptic
/// loop touches) and `meshes`.
struct BenchSite {
    /// Contours `m` and makes the sculpt thread (not started). Throws what SculptThread's constructor throws.
    explicit BenchSite(compute::TriDexel m) : model(std::move(m)), contourer(model) {
        contourer.update(model);
        thread = std::make_unique<app::SculptThread>(model, contourer, ring, surface, Vec3(0.0));
    }
    /// Hands the sculpt thread a companion's options (its stream and setup) and per-tile mesh publishing.
    void wire(const app::SculptOptions& o) {
        for (compute::ToolStreamSink* s : o.streams) thread->use_stream(*s);
        for (const auto& f : o.sculpt_setup) f(*thread);
        thread->publish_mesh_to(meshes, 0.0, app::MeshForm::kTiles);
    }
    /// Takes the newest publish, if new: its publish time and the device time of its oldest cutting sample. One
    /// thread only.
    void take() {
        const app::MeshFrame& f = meshes.latest();
        if (f.version != last_version && std::isfinite(f.oldest_sample_t_s)) seen.push_back({f.published_s, f.oldest_sample_t_s});
        last_version = f.version;
    }
    compute::TriDexel model;
    compute::Contourer contourer;
    SpscRing<ToolSample> ring{8192};
    TripleBuffer<ActiveSurface> surface;
    TripleBuffer<app::MeshFrame> meshes;
    std::unique_ptr<app::SculptThread> thread;
    std::uint64_t last_version = 0;
    std::vector<std::pair<double, double>> seen;  ///< (published_s, oldest_sample_t_s), s
};

/// The groove a site carves: n (>= 2) samples along x at height y_m (m) on the box's top face, device times from t0_s
/// (s, 1 ms apart), a ball of 4 mm; one more sample ends the stroke.
inline std::vector<ToolSample> groove(double y_m, double t0_s, int n) {
    std::vector<ToolSample> s(static_cast<std::size_t>(n) + 1);
    for (int i = 0; i <= n; ++i) {
        ToolSample& x = s[static_cast<std::size_t>(i)];
        x.t_s = t0_s + i * 1e-3;
        x.position = Vec3(-0.03 + 0.06 * std::min(i, n - 1) / (n - 1), y_m, 0.046);
        x.tool.radius_m = 0.004;
        x.op = i < n ? ToolOp::kSubtract : ToolOp::kNone;
    }
    return s;
}

/// Pushes each site's samples (either may be empty) at 1 kHz on the wall clock, noting each push time (now_s()) by
/// device time in ms in `pushed` (which must hold every sample's index), taking both sites' publishes meanwhile.
inline void carve(BenchSite& hs, const std::vector<ToolSample>& a, BenchSite& js, const std::vector<ToolSample>& b,
                  std::vector<double>& pushed) {
    const auto push = [&pushed](BenchSite& site, ToolSample x) {
        x.made_s = now_s();
        pushed[static_cast<std::size_t>(std::lround(x.t_s * 1e3))] = x.made_s;
        while (!site.ring.try_push(x)) std::this_thread::yield();
    };
    const auto start = Clock::now();
    for (std::size_t i = 0; i < std::max(a.size(), b.size()); ++i) {
        std::this_thread::sleep_until(start + std::chrono::microseconds(1000 * i));
        if (i < a.size()) push(hs, a[i]);
        if (i < b.size()) push(js, b[i]);
        hs.take();
        js.take();
    }
}

/// The session key both ends of a benchmark's session are sealed with (fixed bytes: nothing secret is at stake).
inline devices::net::SessionKey bench_key() {
    std::uint8_t kb[devices::net::SessionKey::kBytes];
    for (std::size_t i = 0; i < sizeof kb; ++i) kb[i] = static_cast<std::uint8_t>(7 * i + 1);
    return devices::net::SessionKey(kb);
}

/// The starting model: a box of 97.4 mm in a lattice of `resolution` cells along its 0.1 m side, centred on the
/// origin (its top face at z = 48.7 mm). Throws what TriDexel::empty throws for a bad resolution.
inline compute::TriDexel bench_box(int resolution) {
    compute::TriDexel m = compute::TriDexel::empty(compute::Lattice::around(Aabb{Vec3(-0.05), Vec3(0.05)}, resolution),
                                                   std::size_t{1} << 31);
    compute::scan_convert(box_mesh(Aabb{Vec3(-0.0487), Vec3(0.0487)}), m);
    return m;
}

/// Wires `hs`'s sculpt thread to `host`, starts the host on `m` (a run session's way: the starting model's file in the
/// host's out folder, late joiners getting the model as it stands) and starts the thread. Throws as SharedHost does.
inline void start_host_site(app::SharedHost& host, BenchSite& hs, const compute::TriDexel& m) {
    app::SculptOptions o;
    host.configure(o);
    hs.wire(o);
    app::Workpiece wp;
    wp.model = m;
    app::start_shared_host(host, wp, app::SessionSpec{});
    hs.thread->start();
}

/// Joins through `join`, builds the joiner's site on the model the host sent, wires its sculpt thread to follow the
/// host and starts it. Throws as SharedJoin::join does.
inline std::unique_ptr<BenchSite> join_site(app::SharedJoin& join) {
    const app::SharedJoin::Joined joined = join.join();
    auto js = std::make_unique<BenchSite>(compute::load_tdx(joined.start_path, std::size_t{1} << 31).model);
    app::SculptOptions o;
    join.configure(o);
    js->wire(o);
    js->thread->start();
    return js;
}

}  // namespace tridex::bench::shared_sites
