// Specks at stroke ends (app::SculptHistory::remove_islands): a stroke that cuts a knob's neck removes the knob's
// floating top when it closes, on the CPU and the GPU path alike (GPU slabs and CPU model agree); undo restores the
// speck bit for bit and redo removes it again; with removal off the speck stays.
#include <gtest/gtest.h>

#include <optional>

#include "compute/model/islands.hpp"
#include "compute/runtime/boolean_backend.hpp"
#include "compute/runtime/sculpt_history.hpp"
#include "gpu/context.hpp"
#include "island_models.hpp"

namespace tridex::app {
namespace {

using compute::Sweep;
using compute::TriDexel;
using compute::test::compare;
using compute::test::knob_model;

struct Path {
    std::optional<gpu::Context> ctx;
    TriDexel model = knob_model();
    std::unique_ptr<BooleanBackend> backend;
    explicit Path(bool gpu) {
        if (gpu) {
            ctx.emplace(gpu::Context::create({}));
            backend = make_boolean_backend_on(model, {BackendMode::kGpu}, *ctx).backend;
        } else {
            backend = make_cpu_backend(model);
        }
    }
    TriDexel stored() const {  // the GPU slabs decoded, or the CPU model
        if (!backend->gpu_slabs()) return model;
        TriDexel d = TriDexel::empty(model.lattice, std::size_t{1} << 30);
        backend->gpu_slabs()->download(d);
        return d;
    }
};

// The CPU reference: the model after `sweeps`, one by one.
TriDexel applied(TriDexel m, const std::vector<Sweep>& sweeps) {
    for (const Sweep& s : sweeps) compute::apply_sweep(m, s);
    return m;
}

void stroke(SculptHistory& h, const std::vector<Sweep>& s) {
    const std::size_t half = s.size() / 2;  // in two batches, as the sculpt thread might
    h.apply(std::span<const Sweep>(s).first(half));
    h.apply(std::span<const Sweep>(s).subspan(half));
}

void cut_knob(bool gpu) {
    Path p(gpu);
    const TriDexel before = p.model;
    const std::vector<Sweep> cut = compute::test::knob_cut(p.model.lattice);
    const TriDexel carved = applied(before, cut);  // the knob's top floats
    // The block alone carved by the same stroke: what is left once the knob's top is gone.
    const TriDexel want = applied(knob_model(false), cut);
    ASSERT_GT(compare(carved, want).rays, 0u) << "the stroke must leave the knob's top floating";

    SculptHistory h(p.model, *p.backend);
    h.remove_islands(true);
    stroke(h, cut);
    IslandRemoval r;
    EXPECT_EQ(h.end_stroke(nullptr, &r), 1u);
    EXPECT_EQ(r.searches, 1u);
    EXPECT_EQ(r.specks, 1u);
    const double cell3 = 1e-9;
    EXPECT_GT(r.volume_m3, 40.0 * cell3);
    EXPECT_LT(r.volume_m3, compute::speck_volume_m3(compute::test::kKnobToolCells * 1e-3));
    EXPECT_EQ(h.islands().specks, 1u);
    EXPECT_EQ(compare(p.model, want).rays, 0u) << "the speck is gone, nothing else changed";
    EXPECT_EQ(compare(p.stored(), p.model).rays, 0u) << "the GPU slabs agree with the CPU model";
    EXPECT_TRUE(std::any_of(p.model.tiles.dirty.begin(), p.model.tiles.dirty.end(), [](std::uint8_t d) { return d != 0; }));

    // Undo brings the speck back with the stroke, to the bit; redo removes it again.
    EXPECT_EQ(h.undo().serial, 1u);
    EXPECT_EQ(compare(p.model, before).rays, 0u);
    EXPECT_EQ(compare(p.stored(), before).rays, 0u);
    EXPECT_EQ(h.redo().serial, 1u);
    EXPECT_EQ(compare(p.model, want).rays, 0u);
    EXPECT_EQ(compare(p.stored(), want).rays, 0u);
    EXPECT_EQ(h.islands().specks, 1u) << "redo is not a new removal";
}

TEST(SculptHistoryIslands, AStrokeThatCutsAKnobLooseRemovesItsTopOnTheCpu) { cut_knob(false); }

TEST(SculptHistoryIslands, AStrokeThatCutsAKnobLooseRemovesItsTopOnTheGpu) { cut_knob(true); }

TEST(SculptHistoryIslands, WithRemovalOffTheSpeckStays) {
    Path p(false);
    const std::vector<Sweep> cut = compute::test::knob_cut(p.model.lattice);
    const TriDexel carved = applied(p.model, cut);
    SculptHistory h(p.model, *p.backend);
    EXPECT_FALSE(h.removes_islands());
    stroke(h, cut);
    IslandRemoval r;
    h.end_stroke(nullptr, &r);
    EXPECT_EQ(r.searches, 0u);
    EXPECT_EQ(r.specks, 0u);
    EXPECT_EQ(compare(p.model, carved).rays, 0u);
}

TEST(SculptHistoryIslands, AStrokeClosedByUndoRemovesItsSpecksFirstAndUnionStrokesNeverRemove) {
    Path p(false);
    const TriDexel before = p.model;
    const std::vector<Sweep> cut = compute::test::knob_cut(p.model.lattice);
    SculptHistory h(p.model, *p.backend);
    h.remove_islands(true);
    stroke(h, cut);
    EXPECT_EQ(h.undo().serial, 1u);  // closes the stroke (removing the speck), then undoes it
    EXPECT_EQ(h.islands().specks, 1u);
    EXPECT_EQ(compare(p.model, before).rays, 0u);
    // A small ball added in the air (a union stroke) is not a cut: it stays.
    Sweep blob;
    blob.op = ToolOp::kUnion;
    blob.tool = compute::SweepTool{ToolKind::kBall, 2e-3, 0.0};
    const Vec3 c = p.model.lattice.to_world(Vec3(40.0));
    blob.path_m = Segment{c, c};
    const TriDexel with_blob = applied(p.model, {blob});
    h.apply(std::span<const Sweep>(&blob, 1));
    h.end_stroke();
    EXPECT_EQ(compare(p.model, with_blob).rays, 0u);
    EXPECT_EQ(h.islands().searches, 1u);
}

}  // namespace
}  // namespace tridex::app
