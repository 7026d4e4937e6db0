// Symmetry in the session journal: the sculpt thread applies each sample's symmetric copies in the same batch and
// stroke, the journal carries the symmetry (version 3), a replay of it gives the same dexels bit for bit, and a
// version 2 journal (no symmetry bytes) still reads.
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "compute/journal/journal_format.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_replay.hpp"
#include "compute/journal/journal_writer.hpp"
#include "compute/mesh/scan_convert.hpp"
#include "compute/model/model_digest.hpp"
#include "compute/runtime/sculpt_thread.hpp"
#include "journalled_session.hpp"
#include "compute/tools/sample_sweep.hpp"
#include "core/crc32.hpp"
#include "core/primitives.hpp"

namespace tridex::app {
namespace {

namespace fs = std::filesystem;

compute::TriDexel box_model() {
    compute::TriDexel m =
        compute::TriDexel::empty(compute::Lattice::around(Aabb{Vec3(-0.05), Vec3(0.05)}, 40), std::size_t(1) << 30);
    compute::scan_convert(box_mesh(Aabb{Vec3(-0.0487), Vec3(0.0487)}), m);
    return m;
}

// Three strokes: subtract under mirror x, union under radial 5 about z, push (clay) under mirror yz.
std::vector<ToolSample> stream() {
    std::vector<ToolSample> s(300);
    for (int i = 0; i < 300; ++i) {
        const double u = (i % 100) / 99.0;
        s[i].t_s = i * 1e-3;
        s[i].position = Vec3(0.01 + 0.03 * u, 0.02 * std::sin(9.0 * u) - 0.01, 0.046 - 0.003 * std::sin(5.0 * u));
        s[i].tool.radius_m = 0.005;
        const int stroke = i / 100;
        s[i].op = stroke == 0 ? ToolOp::kSubtract : stroke == 1 ? ToolOp::kUnion : ToolOp::kPush;
        s[i].material = 3;
        s[i].symmetry = parse_symmetry(stroke == 0 ? "x" : stroke == 1 ? "radial:5:z" : "yz", "test");
    }
    return s;
}

std::vector<unsigned char> file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(JournalSymmetry, SamplesKeepTheirSymmetryAndBadSymmetryBytesAreRefused) {
    for (const char* name : {"off", "x", "xz", "xyz", "radial:2:x", "radial:32:z", "radial:9:y"}) {
        ToolSample s, back;
        s.symmetry = parse_symmetry(name, "t");
        unsigned char b[compute::kJournalSampleBytes];
        compute::encode_sample(s, b);
        ASSERT_TRUE(compute::decode_sample(b, back)) << name;
        EXPECT_EQ(back.symmetry, s.symmetry) << name;
        if (!s.symmetry.on()) {
            EXPECT_EQ(b[115] | get_u32(b + 116), 0u);  // as versions 1 and 2 wrote it
        }
    }
    ToolSample s, back;
    unsigned char b[compute::kJournalSampleBytes];
    compute::encode_sample(s, b);
    unsigned char bad = b[115];
    b[115] = 0x08;  // an unused bit
    EXPECT_FALSE(compute::decode_sample(b, back));
    b[115] = 0x01;  // mirror x with radial copies
    put_u32(b + 116, 4);
    EXPECT_FALSE(compute::decode_sample(b, back));
    b[115] = bad;
    put_u32(b + 116, 33);  // too many copies
    EXPECT_FALSE(compute::decode_sample(b, back));
    put_u32(b + 116, 1);
    EXPECT_FALSE(compute::decode_sample(b, back));
}

TEST(JournalSymmetry, AJournalWrittenWithSymmetryReplaysToTheSameDexels) {
    const std::string path = (fs::temp_directory_path() / ("tridex_journal_sym_" + std::to_string(::getpid()) + ".tdj")).string();
    compute::TriDexel live = box_model();
    std::size_t strokes = 0;
    {
        const test::JournalledRun run = test::sculpt_journalled(live, stream(), path);  // the batches depend on timing
        EXPECT_EQ(run.journal.error, "");
        // Each stroke's first sweep starts at the previous stroke's last sample; every copy is counted.
        EXPECT_EQ(run.sculpt.booleans, 99u * 2u + 100u * 5u + 100u * 4u);
    }
    const compute::Journal j = compute::read_journal(path);
    EXPECT_EQ(j.version, compute::kJournalVersion);
    std::size_t at = 0;
    const auto samples = stream();
    for (const compute::JournalRecord& r : j.records) {
        if (r.kind == compute::JournalKind::kStrokeEnd) ++strokes;
        for (const ToolSample& s : r.samples) EXPECT_EQ(s.symmetry, samples[at++].symmetry);
    }
    EXPECT_EQ(at, samples.size());
    EXPECT_EQ(strokes, 3u);  // each stroke with its copies is one undo step

    compute::TriDexel again = box_model();
    const compute::JournalApplyStats st = compute::journal_apply(again, j.records);
    EXPECT_EQ(st.samples, 300u);
    EXPECT_EQ(compute::model_digest(again), compute::model_digest(live));

    // The mirrored cut is visible: without the symmetry bytes the replay differs.
    std::vector<compute::JournalRecord> plain = j.records;
    for (compute::JournalRecord& r : plain)
        for (ToolSample& s : r.samples) s.symmetry = Symmetry{};
    compute::TriDexel one_sided = box_model();
    compute::journal_apply(one_sided, plain);
    EXPECT_NE(compute::model_digest(one_sided), compute::model_digest(live));

    fs::remove(path);
}

TEST(JournalSymmetry, AVersion2JournalStillReads) {
    const std::string path = (fs::temp_directory_path() / ("tridex_journal_v2_" + std::to_string(::getpid()) + ".tdj")).string();
    std::vector<ToolSample> s = stream();
    for (ToolSample& x : s) x.symmetry = Symmetry{};  // what a version 2 writer could carry
    {
        compute::JournalWriter w(path, "session", std::chrono::milliseconds(100));
        w.append(std::span<const ToolSample>(s).subspan(0, 100));
        w.close();
    }
    std::vector<unsigned char> bytes = file_bytes(path);
    const std::uint32_t len = get_u32(bytes.data() + 16);
    put_u32(bytes.data() + 8, 2);
    put_u32(bytes.data() + compute::kJournalHeaderFixedBytes + len,
            crc32_ieee(bytes.data(), compute::kJournalHeaderFixedBytes + len));
    const compute::Journal j = compute::parse_journal(bytes, "v2.tdj");
    EXPECT_EQ(j.version, 2u);
    ASSERT_EQ(j.records.size(), 1u);
    ASSERT_EQ(j.records[0].samples.size(), 100u);
    for (const ToolSample& x : j.records[0].samples) EXPECT_FALSE(x.symmetry.on());
    compute::TriDexel a = box_model(), b = box_model();
    compute::journal_apply(a, j.records);
    std::vector<compute::Sweep> batch;
    for (std::size_t i = 1; i < 100; ++i) compute::sample_sweeps(s[i - 1], s[i], nullptr, nullptr, Vec3(0.0), batch);
    for (const compute::Sweep& sw : batch) compute::apply_sweep(b, sw);
    EXPECT_EQ(compute::model_digest(a), compute::model_digest(b));
    fs::remove(path);
}

}  // namespace
}  // namespace tridex::app
