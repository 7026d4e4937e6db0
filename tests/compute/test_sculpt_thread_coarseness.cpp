// The model's coarseness changed during a session (SculptHistory::resample, SculptRequest kFiner and kCoarser): one
// undo step whose undo puts the old lattice back bit for bit, journalled so that a recovery and a replay of the marks
// rebuild the same model, and refused, with a line saying why, where it cannot be followed. CPU only (run under
// ThreadSanitizer).
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <limits>
#include <thread>

#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "core/error.hpp"
#include "sculpt_passes.hpp"
#include "sweep_programs.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;
using compute::Sweep;
using compute::TriDexel;
using compute::model_digest;
using compute::test::box_model;

constexpr int kCells = 48;
constexpr std::size_t kNoLimit = std::numeric_limits<std::size_t>::max();
TriDexel fresh() { return box_model(kCells, 6.5, 41.5); }

bool same_lattice(const compute::Lattice& a, const compute::Lattice& b) {
    return a.cells == b.cells && a.cell_m == b.cell_m && a.origin_m == b.origin_m;
}

bool all_dirty(const TriDexel& m) {
    for (const std::uint8_t d : m.tiles.dirty)
        if (d == 0) return false;
    return true;
}

void stroke(SculptHistory& h, std::span<const Sweep> s) {
    h.apply(s);
    h.end_stroke();
}

TEST(SculptCoarseness, AChangeIsOneUndoStepWhoseUndoPutsTheOldLatticeBackBitForBit) {
    TriDexel m = fresh();
    const std::uint64_t d_fresh = model_digest(m);
    const compute::Lattice coarse = m.lattice;
    auto backend = make_cpu_backend(m);
    SculptHistory h(m, *backend);
    const std::vector<Sweep> program = compute::test::random_program(m.lattice, 160, 11);
    const std::span<const Sweep> all(program);
    stroke(h, all.first(80));  // serial 1
    const std::uint64_t d_a = model_digest(m);

    compute::ResampleStats rs;
    const compute::UndoHistory::Change c = h.resample(2 * kCells, kNoLimit, &rs);
    EXPECT_TRUE(c.lattice);
    EXPECT_EQ(c.serial, 2u);
    EXPECT_EQ(rs.resolution_before, kCells);
    EXPECT_EQ(rs.resolution_after, 2 * kCells);
    EXPECT_EQ(compute::lattice_resolution(m.lattice), 2 * kCells);
    EXPECT_TRUE(all_dirty(m));
    const compute::Lattice fine = m.lattice;
    const std::uint64_t d_fine = model_digest(m);
    EXPECT_EQ(d_fine, model_digest(compute::resample_model(
                          [&] {
                              TriDexel again = fresh();
                              for (const Sweep& s : all.first(80)) compute::apply_sweep(again, s);
                              return again;
                          }(),
                          2 * kCells, kNoLimit)))
        << "the change is resample_model of the model as it stood";

    stroke(h, all.subspan(80));  // serial 3, on the finer lattice
    const std::uint64_t d_b = model_digest(m);
    EXPECT_EQ(h.next_undo_serial(), 3u);
    EXPECT_EQ(h.lattice_undo_steps(), 1u);
    EXPECT_EQ(h.stats().undo_steps, 3u);

    EXPECT_FALSE(h.undo().lattice);  // stroke 3
    EXPECT_EQ(model_digest(m), d_fine);
    EXPECT_EQ(h.next_undo_serial(), 2u);
    const compute::UndoHistory::Change u = h.undo();  // the change
    EXPECT_TRUE(u.lattice);
    EXPECT_EQ(u.serial, 2u);
    EXPECT_TRUE(same_lattice(m.lattice, coarse));
    EXPECT_EQ(model_digest(m), d_a) << "the old lattice comes back bit for bit";
    EXPECT_TRUE(all_dirty(m));
    EXPECT_EQ(h.undo().serial, 1u);  // the strokes before the change stay undoable
    EXPECT_EQ(model_digest(m), d_fresh);
    EXPECT_EQ(h.undo().serial, 0u);

    EXPECT_EQ(h.redo().serial, 1u);
    EXPECT_EQ(model_digest(m), d_a);
    EXPECT_EQ(h.next_redo_serial(), 2u);
    EXPECT_TRUE(h.redo().lattice);
    EXPECT_TRUE(same_lattice(m.lattice, fine));
    EXPECT_EQ(model_digest(m), d_fine);
    EXPECT_EQ(h.redo().serial, 3u);
    EXPECT_EQ(model_digest(m), d_b);

    // Back across the change, a new stroke on the old lattice drops the change's redo, and takes a new serial.
    h.undo();
    h.undo();
    EXPECT_TRUE(same_lattice(m.lattice, coarse));
    stroke(h, all.subspan(100, 30));
    EXPECT_EQ(h.next_undo_serial(), 4u);
    EXPECT_EQ(h.next_redo_serial(), 0u);
    EXPECT_EQ(h.lattice_redo_steps(), 0u);
    EXPECT_EQ(h.redo().serial, 0u);
    EXPECT_TRUE(same_lattice(m.lattice, coarse));
}

TEST(SculptCoarseness, RefusedWhileAStrokeIsOpenAndFinalWhenTheOldModelOutgrowsTheBudget) {
    TriDexel m = fresh();
    auto backend = make_cpu_backend(m);
    const std::vector<Sweep> program = compute::test::random_program(m.lattice, 40, 5);
    {
        SculptHistory h(m, *backend);
        h.apply(program);
        const std::uint64_t d = model_digest(m);
        EXPECT_THROW(h.resample(2 * kCells, kNoLimit), Error);
        EXPECT_EQ(model_digest(m), d) << "nothing changed";
        h.end_stroke();
        EXPECT_THROW(h.resample(4, kNoLimit), Error) << "below the smallest resolution";
        EXPECT_THROW(h.resample(2 * kCells, 1000), Error) << "over max_bytes";
        EXPECT_EQ(model_digest(m), d);
        h.resample(kCells / 2, kNoLimit);
        try {
            (void)h.save_steps();
            ADD_FAILURE() << "saved steps over a coarseness change";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("coarseness"), std::string::npos) << e.what();
        }
    }
    TriDexel small = fresh();
    auto small_backend = make_cpu_backend(small);
    SculptHistory tight(small, *small_backend, 64 * 1024);  // less than the model itself
    tight.resample(kCells / 2, kNoLimit);
    EXPECT_EQ(tight.lattice_undo_steps(), 0u) << "a model over the budget makes the change final";
    EXPECT_EQ(tight.undo().serial, 0u);
    EXPECT_EQ(compute::lattice_resolution(small.lattice), kCells / 2);
}

using test::pass;
using test::push_all;
using test::wait_drained;

// The session's samples: a cut, a lift, a cut, a lift, a cut, a lift (each request comes between two of them).
std::vector<std::vector<ToolSample>> session_parts() {
    return {pass(-0.01, 0.0, 200, ToolOp::kSubtract), pass(-0.01, 0.2, 5, ToolOp::kNone),
            pass(0.0, 0.3, 200, ToolOp::kSubtract),   pass(0.0, 0.5, 5, ToolOp::kNone),
            pass(0.01, 0.6, 200, ToolOp::kSubtract),  pass(0.01, 0.8, 5, ToolOp::kNone)};
}

struct Ran {
    std::uint64_t digest = 0;
    compute::Lattice lattice;
    SculptStats stats;
    SaveStatus status;
    std::size_t tiles = 0;  // triangles of the Contourer's mesh at the end
};

TEST(SculptCoarseness, RequestsChangeTheLatticeLiveAndTheJournalAndTheMarksRebuildIt) {
    const std::string path = (fs::temp_directory_path() / ("tridex_coarse_" + std::to_string(::getpid()) + ".tdj")).string();
    const auto parts = session_parts();
    Ran live;
    TriDexel model = fresh();
    {
        compute::Contourer contourer(model);
        contourer.update(model);
        SpscRing<ToolSample> ring(4096);
        TripleBuffer<ActiveSurface> surface;
        compute::JournalWriter journal(path, "session", std::chrono::milliseconds(5));
        SculptThread t(model, contourer, ring, surface, Vec3(0.0));
        t.use_journal(journal);
        t.start();
        push_all(ring, parts[0]);
        push_all(ring, parts[1]);
        wait_drained(ring, t);
        EXPECT_TRUE(t.request(SculptRequest::kFiner));  // 48 -> 96
        wait_drained(ring, t);
        EXPECT_NE(t.save_status().coarseness.find("N = 48 -> 96"), std::string::npos) << t.save_status().coarseness;
        EXPECT_EQ(surface.latest().cell_m, model.lattice.cell_m) << "the haptic surface follows the new lattice";
        push_all(ring, parts[2]);
        push_all(ring, parts[3]);
        wait_drained(ring, t);
        EXPECT_TRUE(t.request(SculptRequest::kUndo));  // the second cut
        EXPECT_TRUE(t.request(SculptRequest::kUndo));  // the change: back to 48
        wait_drained(ring, t);
        EXPECT_EQ(compute::lattice_resolution(model.lattice), kCells);
        EXPECT_NE(t.save_status().coarseness.find("change undone, N = 48"), std::string::npos) << t.save_status().coarseness;
        EXPECT_TRUE(t.request(SculptRequest::kRedo));  // the change again
        EXPECT_TRUE(t.request(SculptRequest::kCoarser));  // 96 -> 48: drops the redo of the second cut
        wait_drained(ring, t);
        push_all(ring, parts[4]);
        push_all(ring, parts[5]);
        wait_drained(ring, t);
        t.stop();
        live.stats = t.stats();
        live.status = t.save_status();
        live.tiles = contourer.mesh().triangles.size();
        EXPECT_EQ(journal.stats().error, "");
    }
    live.digest = model_digest(model);
    live.lattice = model.lattice;
    ASSERT_EQ(live.stats.coarseness.size(), 2u);
    EXPECT_EQ(live.stats.coarseness[0].resample.resolution_after, 2 * kCells);
    EXPECT_EQ(live.stats.coarseness[1].resample.resolution_after, kCells);
    EXPECT_GT(live.stats.coarseness[1].serial, live.stats.coarseness[0].serial);
    EXPECT_EQ(live.stats.history.undos, 2u) << "a stroke's and the change's";
    EXPECT_EQ(live.stats.history.redos, 1u);
    EXPECT_EQ(live.stats.history.strokes, 3u) << "the second cut's stroke counts, though its redo is gone";
    EXPECT_NE(live.status.coarseness.find("N = 96 -> 48"), std::string::npos) << live.status.coarseness;
    EXPECT_EQ(compute::lattice_resolution(model.lattice), kCells);
    EXPECT_GT(live.tiles, 0u) << "the Contourer follows the lattice";
    EXPECT_NE(live.digest, model_digest(fresh()));

    // The journal: two lattice records; replayed from the start it ends on the same lattice and dexels.
    const compute::Journal j = compute::read_journal(path);
    std::size_t lattices = 0;
    for (const auto& r : j.records) lattices += r.kind == compute::JournalKind::kLattice;
    EXPECT_EQ(lattices, 2u);
    TriDexel again = fresh();
    const compute::JournalApplyStats st = compute::journal_apply(again, j.records);
    EXPECT_EQ(st.lattices, 2u);
    EXPECT_EQ(st.undos, 2u);
    EXPECT_EQ(st.redos, 1u);
    EXPECT_TRUE(same_lattice(again.lattice, live.lattice));
    EXPECT_EQ(model_digest(again), live.digest) << "recovery rebuilds the model bit for bit";

    // A replay of the samples that follows the live session's marks makes the same changes at the same places.
    TriDexel replayed = fresh();
    {
        compute::Contourer contourer(replayed);
        contourer.update(replayed);
        SpscRing<ToolSample> ring(4096);
        TripleBuffer<ActiveSurface> surface;
        SculptThread t(replayed, contourer, ring, surface, Vec3(0.0));
        t.follow_marks(live.stats.marks);
        t.start();
        for (const auto& p : parts) push_all(ring, p);
        wait_drained(ring, t);
        t.stop();
        EXPECT_EQ(t.stats().coarseness.size(), 2u);
    }
    EXPECT_TRUE(same_lattice(replayed.lattice, live.lattice));
    EXPECT_EQ(model_digest(replayed), live.digest) << "the replay follows the marks bit for bit";
    fs::remove(path);
}

// With levels of detail and coarse groups on the new lattice, the change publishes coarse group levels first and
// contours the tiles after them (as a coarse-first start-up); the session ends with the whole contour of the new model.
TEST(SculptCoarseness, OntoALatticeWithCoarseGroupsTheTilesFollowTheCoarseLevels) {
    TriDexel model = fresh();
    compute::Contourer contourer(model);
    contourer.update(model);
    SpscRing<ToolSample> ring(4096);
    TripleBuffer<ActiveSurface> surface;
    TripleBuffer<MeshFrame> meshes;
    SculptStats stats;
    MeshFrame last;
    {
        SculptThread t(model, contourer, ring, surface, Vec3(0.0));
        compute::LodWorkerOptions lod;
        lod.lod.cell_m = model.lattice.cell_m;
        lod.coarse_groups_from_cells = 64;  // none at 48 cells, coarse groups at 96
        t.use_tile_lod(lod);
        t.publish_mesh_to(meshes, 0.0, MeshForm::kTiles);
        t.start();
        EXPECT_TRUE(t.request(SculptRequest::kFiner));
        wait_drained(ring, t);
        push_all(ring, pass(0.0, 0.0, 200, ToolOp::kSubtract));  // a cut while the tiles are being contoured
        wait_drained(ring, t);
        t.stop();
        stats = t.stats();
        last = meshes.latest();
    }
    ASSERT_EQ(stats.coarseness.size(), 1u);
    EXPECT_GT(stats.startup_tiles_refined, 0u) << "the new lattice's tiles came after its coarse levels";
    compute::Contourer whole(model);
    std::fill(model.tiles.dirty.begin(), model.tiles.dirty.end(), compute::TileGrid::kWhole);
    whole.update(model);
    const TriMesh a = contourer.mesh(), b = whole.mesh();
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.triangles, b.triangles);
    std::size_t triangles = 0;
    for (const auto& tile : last.tiles) triangles += tile->mesh.triangles.size();
    EXPECT_EQ(triangles, b.triangles.size()) << "the last publish holds every tile of the new lattice";
    for (const auto& g : last.groups) EXPECT_TRUE(g->children_cover) << g->id;
}

// A sink that follows the stream (a cluster wall's ranks, a shared session's joiners).
struct NullSink final : compute::ToolStreamSink {
    void append(std::span<const ToolSample>) override {}
    void mark(std::uint32_t, std::uint64_t, std::uint64_t) override {}
};

TEST(SculptCoarseness, RefusedWithAReasonWhereTheModelIsSharedOrTheLatticeWouldLeaveItsRange) {
    TriDexel model = fresh();
    const std::uint64_t d = model_digest(model);
    compute::Contourer contourer(model);
    contourer.update(model);
    SpscRing<ToolSample> ring(4096);
    TripleBuffer<ActiveSurface> surface;
    {
        NullSink sink;
        SculptThread t(model, contourer, ring, surface, Vec3(0.0));
        t.use_stream(sink);
        t.start();
        EXPECT_TRUE(t.request(SculptRequest::kFiner));
        wait_drained(ring, t);
        t.stop();
        EXPECT_NE(t.save_status().coarseness.find("refused"), std::string::npos) << t.save_status().coarseness;
        EXPECT_NE(t.save_status().coarseness.find("shared"), std::string::npos) << t.save_status().coarseness;
        EXPECT_TRUE(t.stats().coarseness.empty());
    }
    EXPECT_EQ(model_digest(model), d);
    {
        SculptThread t(model, contourer, ring, surface, Vec3(0.0));
        t.use_lattice_check([](const TriDexel&, int resolution) -> std::size_t {
            if (resolution > 2 * kCells) throw Error("coarseness N = " + std::to_string(resolution) + " would need 9 GB");
            return kNoLimit;
        });
        t.start();
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(t.request(SculptRequest::kCoarser));  // 24, 12, then 6: refused
        wait_drained(ring, t);
        EXPECT_NE(t.save_status().coarseness.find("outside 8..4096"), std::string::npos) << t.save_status().coarseness;
        for (int k = 0; k < 4; ++k) EXPECT_TRUE(t.request(SculptRequest::kFiner));  // 24, 48, 96, then 192: refused
        wait_drained(ring, t);
        EXPECT_NE(t.save_status().coarseness.find("would need 9 GB"), std::string::npos) << t.save_status().coarseness;
        t.stop();
        EXPECT_EQ(t.stats().coarseness.size(), 5u);
    }
    EXPECT_EQ(compute::lattice_resolution(model.lattice), 2 * kCells);
}

}  // namespace
}  // namespace tridex::app
