// A live session's memory estimated from its model before its contour is built: the contour's triangles counted from
// the model's intervals (4 per interval) against the contour Zhang and Leu's dual contouring actually makes, on a
// sphere and the bunny at several resolutions; and the refusal that names what it would need and what there is.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "app/scene/session_memory.hpp"
#include "app/scene/workpiece_source.hpp"
#include "app/support/assets.hpp"
#include "app/support/memory.hpp"
#include "compute/contour/contour_dual.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "core/error.hpp"
#include "core/primitives.hpp"

namespace tridex::app {
namespace {

std::size_t contour_triangles(compute::TriDexel& model) {
    compute::Contourer c(model);
    c.update(model);
    return c.stats().triangles;
}

TEST(SessionMemory, TheContoursTrianglesAreFourPerInterval) {
    for (const int n : {48, 96, 192}) {
        Workpiece bunny = prepare_workpiece(default_mesh_path(), n, 0.2, Vec3(0.0));
        const SessionMemory m = estimate_session_memory(bunny.model, SessionKind::kLive);
        const std::size_t real = contour_triangles(bunny.model);
        std::printf("bunny N = %d: estimated %llu triangles, contoured %zu\n", n,
                    static_cast<unsigned long long>(m.triangles), real);
        EXPECT_NEAR(static_cast<double>(m.triangles), static_cast<double>(real), 0.05 * static_cast<double>(real)) << n;
        EXPECT_EQ(m.contour_bytes, m.triangles * kLiveBytesPerTriangle);
        EXPECT_EQ(m.total_bytes, m.model_bytes + m.contour_bytes + m.base_bytes);
        EXPECT_GT(m.model_bytes, bunny.model.interval_count() * sizeof(compute::Interval));
    }
    // A sphere: its contour grows with the square of the resolution, and so does the estimate.
    const TriMesh ball = icosphere_mesh(Vec3(0.0), 0.05, 4);
    std::uint64_t prev = 0;
    for (const int n : {32, 64, 128}) {
        compute::TriDexel model = compute::TriDexel::empty(compute::Lattice::around(ball.bounds(), n), std::size_t(1) << 32);
        compute::scan_convert(ball, model);
        const SessionMemory m = estimate_session_memory(model, SessionKind::kBatch);
        const std::size_t real = contour_triangles(model);
        EXPECT_NEAR(static_cast<double>(m.triangles), static_cast<double>(real), 0.05 * static_cast<double>(real)) << n;
        if (prev) {
            EXPECT_NEAR(static_cast<double>(m.triangles) / static_cast<double>(prev), 4.0, 0.7) << n;  // padding cells at low N
        }
        prev = m.triangles;
    }
}

TEST(SessionMemory, AMeshsEstimateFromACoarseScanMatchesItsOwnScan) {
    SessionSpec spec;
    spec.mesh_path = default_mesh_path();
    spec.stock_m = 0.2;
    spec.workpiece_centre_m = Vec3(0.0);
    spec.resolution = 384;
    const std::optional<SessionMemory> up_front = estimate_session_memory_of_mesh(spec, SessionKind::kLive);
    ASSERT_TRUE(up_front.has_value());
    Workpiece wp = prepare_workpiece(spec.mesh_path, spec.resolution, spec.stock_m, spec.workpiece_centre_m);
    const SessionMemory built = estimate_session_memory(wp.model, SessionKind::kLive);
    std::printf("N = 384: %llu triangles from the scan at %d, %llu from its own\n",
                static_cast<unsigned long long>(up_front->triangles), kMemoryProbeResolution,
                static_cast<unsigned long long>(built.triangles));
    EXPECT_NEAR(static_cast<double>(up_front->triangles), static_cast<double>(built.triangles), 0.1 * static_cast<double>(built.triangles));
    EXPECT_NEAR(static_cast<double>(up_front->total_bytes), static_cast<double>(built.total_bytes), 0.1 * static_cast<double>(built.total_bytes));
    spec.resolution = kMemoryProbeResolution;  // nothing finer to estimate: its own scan is as quick
    EXPECT_FALSE(estimate_session_memory_of_mesh(spec, SessionKind::kLive).has_value());
    spec.resolution = 512;
    spec.model_path = "saved.tdx";  // checked once loaded
    EXPECT_FALSE(estimate_session_memory_of_mesh(spec, SessionKind::kLive).has_value());
}

TEST(SessionMemory, ALatticeTooFineIsRefusedWithWhatItWouldNeed) {
    SessionMemory need;
    need.model_bytes = 344'000'000;
    need.triangles = 28'700'000;
    need.contour_bytes = need.triangles * kLiveBytesPerTriangle;
    need.base_bytes = kSessionBaseBytes;
    need.total_bytes = need.model_bytes + need.contour_bytes + need.base_bytes;
    ::unsetenv("TRIDEX_IGNORE_MEMORY_ESTIMATE");
    try {
        check_session_memory(need, 8'000'000'000ull, "workpiece.resolution 2048");
        ADD_FAILURE() << "not refused";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("workpiece.resolution 2048: this session would need about 14.5 GB"), std::string::npos) << what;
        EXPECT_NE(what.find("28.7 million triangles"), std::string::npos) << what;
        EXPECT_NE(what.find("this machine has 8.0 GB available"), std::string::npos) << what;
    }
    EXPECT_NO_THROW(check_session_memory(need, 20'000'000'000ull, "workpiece.resolution 2048"));
    EXPECT_NO_THROW(check_session_memory(need, 0, "workpiece.resolution 2048")) << "unknown memory: not refused";
    ::setenv("TRIDEX_IGNORE_MEMORY_ESTIMATE", "1", 1);
    EXPECT_NO_THROW(check_session_memory(need, 8'000'000'000ull, "workpiece.resolution 2048"));
    ::unsetenv("TRIDEX_IGNORE_MEMORY_ESTIMATE");
    EXPECT_GT(available_memory_bytes(), 0u) << "this machine says what it has";
    EXPECT_EQ(memory_text(86'000'000), "86 MB");
}

}  // namespace
}  // namespace tridex::app
