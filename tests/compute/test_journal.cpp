// The session journal's file format: bit-exact round trips, torn tails cut at the last valid record, damaged records
// skipped up to the next intact one,
// refused headers, and a writer whose disk fails without stopping its caller.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <thread>

#include "compute/journal/journal_format.hpp"
#include "compute/journal/journal_reader.hpp"
#include "compute/journal/journal_writer.hpp"
#include "core/crc32.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
    return (fs::temp_directory_path() / ("tridex_journal_" + std::to_string(::getpid()) + "_" + name)).string();
}

std::vector<unsigned char> file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Samples with awkward doubles (NaN payloads where a NaN is allowed, -0, denormals) and every field set, all within
// what the reader accepts (finite pose and time, tool sizes >= 0, material ids 0..kMaxMaterialId).
std::vector<ToolSample> odd_samples(std::size_t n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<ToolSample> v(n);
    for (std::size_t i = 0; i < n; ++i) {
        ToolSample& s = v[i];
        s.t_s = 1e-3 * static_cast<double>(i) + u(rng) * 1e-9;
        s.position = Vec3(u(rng), u(rng), u(rng));
        s.surface_m = (i % 3 == 0) ? Vec3(std::numeric_limits<double>::quiet_NaN()) : Vec3(u(rng), -0.0, 5e-324);
        if (i % 5 == 1) s.surface_m.x = std::bit_cast<double>(std::uint64_t{0x7ff8dead'beef0001});  // NaN payload
        s.orientation = Quat(u(rng), u(rng), u(rng), u(rng));
        s.tool.kind = static_cast<ToolKind>(i % 3);
        s.tool.radius_m = i % 7 == 0 ? 5e-324 : 0.004 + 1e-3 * u(rng);
        s.tool.length_m = i % 11 == 0 ? -0.0 : 0.02 * std::fabs(u(rng));
        s.tool.mesh_id = static_cast<std::uint32_t>(rng());
        s.op = static_cast<ToolOp>(i % 4);
        s.material = static_cast<std::uint8_t>(rng() % (kMaxMaterialId + 1u));
        s.buttons = static_cast<std::uint32_t>(rng());
        if (i % 4 == 1) s.symmetry.mirrors = static_cast<std::uint8_t>(i % 8);
        if (i % 4 == 2) s.symmetry = Symmetry{0, static_cast<std::uint8_t>(i % 3), static_cast<std::uint16_t>(2 + i % 31)};
    }
    return v;
}

template <class T>
bool same_bits(const T& a, const T& b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

void expect_same(const ToolSample& a, const ToolSample& b) {
    EXPECT_TRUE(same_bits(a.t_s, b.t_s));
    for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(same_bits(a.position[k], b.position[k]));
        EXPECT_TRUE(same_bits(a.surface_m[k], b.surface_m[k]));
    }
    EXPECT_TRUE(same_bits(a.orientation.w, b.orientation.w) && same_bits(a.orientation.x, b.orientation.x) &&
                same_bits(a.orientation.y, b.orientation.y) && same_bits(a.orientation.z, b.orientation.z));
    EXPECT_EQ(a.tool.kind, b.tool.kind);
    EXPECT_TRUE(same_bits(a.tool.radius_m, b.tool.radius_m));
    EXPECT_TRUE(same_bits(a.tool.length_m, b.tool.length_m));
    EXPECT_EQ(a.tool.mesh_id, b.tool.mesh_id);
    EXPECT_EQ(a.op, b.op);
    EXPECT_EQ(a.material, b.material);
    EXPECT_EQ(a.buttons, b.buttons);
    EXPECT_EQ(a.symmetry, b.symmetry);
}

// Writes `batches` (sizes) of odd samples; returns the samples in order.
std::vector<ToolSample> write_journal(const std::string& path, const std::vector<std::size_t>& batches,
                                      std::size_t buffer_bytes = std::size_t{1} << 18) {
    std::size_t total = 0;
    for (std::size_t b : batches) total += b;
    const std::vector<ToolSample> all = odd_samples(total, 7);
    JournalWriter w(path, R"({"mesh_path":"x.off","mesh_crc32":1})", std::chrono::milliseconds(100), buffer_bytes);
    std::size_t at = 0;
    for (std::size_t b : batches) {
        w.append(std::span<const ToolSample>(all).subspan(at, b));
        at += b;
    }
    w.close();
    EXPECT_EQ(w.stats().error, "");
    EXPECT_EQ(w.stats().records, batches.size());
    EXPECT_EQ(w.stats().samples, total);
    EXPECT_EQ(w.stats().bytes, fs::file_size(path));
    return all;
}

TEST(Journal, RoundTripsSamplesBitForBitInTheirBatches) {
    const std::string path = temp_path("roundtrip.tdj");
    const std::vector<std::size_t> batches{1, 3, 17, 1, 250, 2};
    // A buffer smaller than the 250-sample record streams it through.
    const std::vector<ToolSample> all = write_journal(path, batches, 4096);
    const Journal j = read_journal(path);
    EXPECT_EQ(j.version, kJournalVersion);
    EXPECT_EQ(j.session, R"({"mesh_path":"x.off","mesh_crc32":1})");
    EXPECT_FALSE(j.cut);
    ASSERT_EQ(j.records.size(), batches.size());
    std::size_t at = 0;
    for (std::size_t r = 0; r < batches.size(); ++r) {
        ASSERT_EQ(j.records[r].samples.size(), batches[r]);
        for (const ToolSample& s : j.records[r].samples) expect_same(s, all[at++]);
    }
    EXPECT_EQ(j.samples, all.size());
    fs::remove(path);
}

// Samples no session writes (a non-finite time, pose or tool size, a negative tool size, a material past the
// palette) are damage: the journal is cut at their record, the reason naming the sample and the field.
TEST(Journal, SamplesNoSessionWritesAreCutAtTheirRecord) {
    struct Case {
        const char* what;
        void (*spoil)(ToolSample&);
        const char* reason;
    };
    const Case cases[] = {
        {"nan time", [](ToolSample& s) { s.t_s = std::nan(""); }, "sample 1: t_s = nan is not finite"},
        {"inf position", [](ToolSample& s) { s.position.y = INFINITY; }, "sample 1: position is not finite"},
        {"nan orientation", [](ToolSample& s) { s.orientation.x = std::nan(""); }, "sample 1: orientation is not finite"},
        {"nan radius", [](ToolSample& s) { s.tool.radius_m = std::nan(""); }, "sample 1: tool.radius_m = nan"},
        {"negative radius", [](ToolSample& s) { s.tool.radius_m = -1.0; }, "sample 1: tool.radius_m = -1 must be"},
        {"inf length", [](ToolSample& s) { s.tool.length_m = INFINITY; }, "sample 1: tool.length_m = inf"},
        {"material 250", [](ToolSample& s) { s.material = 250; }, "sample 1: material = 250 is not a material id"},
    };
    for (const Case& c : cases) {
        const std::string path = temp_path("spoiled.tdj");
        std::vector<ToolSample> v = odd_samples(6, 3);
        c.spoil(v[4]);  // the second sample of the second batch
        {
            JournalWriter w(path, "{}");
            w.append(std::span<const ToolSample>(v).subspan(0, 3));
            w.append(std::span<const ToolSample>(v).subspan(3, 3));
            w.close();
        }
        const Journal j = read_journal(path);
        ASSERT_EQ(j.records.size(), 1u) << c.what;
        ASSERT_TRUE(j.cut) << c.what;
        EXPECT_EQ(j.cut->record, 1u) << c.what;
        EXPECT_NE(j.cut->reason.find(c.reason), std::string::npos) << c.what << ": " << j.cut->reason;
        fs::remove(path);
    }
}

TEST(Journal, EmptyBatchesWriteNothing) {
    const std::string path = temp_path("empty.tdj");
    JournalWriter w(path, "{}");
    w.append({});
    w.close();
    const Journal j = read_journal(path);
    EXPECT_TRUE(j.records.empty());
    EXPECT_FALSE(j.cut);
    fs::remove(path);
}

TEST(Journal, TruncatedAtEveryByteOfTheLastRecordsIsCutAtTheLastValidRecord) {
    const std::string path = temp_path("trunc.tdj");
    write_journal(path, {2, 5, 1, 4, 3});
    const std::vector<unsigned char> bytes = file_bytes(path);
    const Journal full = parse_journal(bytes, "full");
    ASSERT_EQ(full.records.size(), 5u);
    std::vector<std::uint64_t> ends;  // end offset of each record
    for (std::size_t r = 1; r < full.records.size(); ++r) ends.push_back(full.records[r].offset);
    ends.push_back(bytes.size());
    for (std::size_t len = full.records[2].offset; len < bytes.size(); ++len) {
        const Journal j = parse_journal(std::span(bytes).first(len), "cut");
        std::size_t complete = 0;
        while (complete < ends.size() && ends[complete] <= len) ++complete;
        ASSERT_EQ(j.records.size(), complete) << "length " << len;
        const bool at_boundary = complete > 0 && ends[complete - 1] == len;
        ASSERT_EQ(j.cut.has_value(), !at_boundary) << "length " << len;
        if (j.cut) {
            EXPECT_EQ(j.cut->record, complete);
            EXPECT_EQ(j.cut->byte_offset, full.records[complete].offset);
            EXPECT_NE(j.cut->reason.find("partial record"), std::string::npos) << j.cut->reason;
        }
    }
    fs::remove(path);
}

TEST(Journal, BitFlipsInRecordsSkipTheFlippedRecord) {
    const std::string path = temp_path("flip.tdj");
    write_journal(path, {2, 3, 1});
    const std::vector<unsigned char> bytes = file_bytes(path);
    const Journal full = parse_journal(bytes, "full");
    for (std::size_t at = full.records[0].offset; at < bytes.size(); ++at) {
        std::size_t hit = 0;  // the record holding byte `at`
        while (hit + 1 < full.records.size() && full.records[hit + 1].offset <= at) ++hit;
        for (int bit = 0; bit < 8; ++bit) {
            std::vector<unsigned char> b = bytes;
            b[at] ^= static_cast<unsigned char>(1u << bit);
            const Journal j = parse_journal(b, "flip");
            if (hit + 1 == full.records.size()) {  // the last record: nothing intact follows, the tail is cut
                ASSERT_EQ(j.records.size(), hit) << "byte " << at << " bit " << bit;
                ASSERT_TRUE(j.cut);
                EXPECT_EQ(j.cut->record, hit);
                EXPECT_EQ(j.cut->byte_offset, full.records[hit].offset);
                continue;
            }
            // Any other record: skipped, and reading resumes at the next one.
            ASSERT_EQ(j.records.size(), full.records.size() - 1) << "byte " << at << " bit " << bit;
            EXPECT_FALSE(j.cut);
            ASSERT_EQ(j.damage.size(), 1u);
            EXPECT_EQ(j.damage[0].record, hit);
            EXPECT_EQ(j.damage[0].records_lost, 1u);
            EXPECT_EQ(j.damage[0].byte_offset, full.records[hit].offset);
            EXPECT_EQ(j.damage[0].bytes, full.records[hit + 1].offset - full.records[hit].offset);
            EXPECT_EQ(j.records[hit].offset, full.records[hit + 1].offset);
            EXPECT_EQ(j.samples, full.samples - full.records[hit].samples.size());
        }
    }
    fs::remove(path);
}

// The message of the Error parse_journal throws for `bytes`; "" when it does not throw.
std::string refusal(const std::vector<unsigned char>& bytes) {
    try {
        parse_journal(bytes, "j.tdj");
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Journal, OtherVersionsGarbageAndDamagedHeadersAreRefusedWithOneLine) {
    const std::string path = temp_path("hdr.tdj");
    write_journal(path, {2});
    const std::vector<unsigned char> bytes = file_bytes(path);
    const std::uint32_t len = get_u32(bytes.data() + 16);

    std::vector<unsigned char> v2 = bytes;  // the next version with a valid header CRC
    put_u32(v2.data() + 8, kJournalVersion + 1);
    put_u32(v2.data() + kJournalHeaderFixedBytes + len, crc32_ieee(v2.data(), kJournalHeaderFixedBytes + len));
    std::vector<unsigned char> damaged = bytes;
    damaged[kJournalHeaderFixedBytes + 3] ^= 0x10;
    const std::vector<unsigned char> garbage(200, 0xAB);
    const std::vector<unsigned char> short_header(bytes.begin(), bytes.begin() + kJournalHeaderFixedBytes + 5);

    const std::pair<std::vector<unsigned char>, std::string> cases[] = {
        {v2, "j.tdj: journal version 7; this build reads versions 1 to 6"},
        {damaged, "j.tdj: the journal header is damaged (CRC mismatch)"},
        {garbage, "j.tdj: not a tridex session journal (no TRDXJNL header)"},
        {{}, "j.tdj: not a tridex session journal (no TRDXJNL header)"},
        {short_header, "j.tdj: the journal header is truncated or damaged"},
    };
    for (const auto& [b, want] : cases) {
        const std::string got = refusal(b);
        EXPECT_EQ(got, want);
        EXPECT_EQ(got.find('\n'), std::string::npos);
    }
    fs::remove(path);
}

TEST(Journal, AFailingDiskStopsTheJournalNotItsCaller) {
    // /dev/full: every write fails with ENOSPC.
    JournalWriter full("/dev/full", "{}");
    EXPECT_FALSE(full.ok());
    EXPECT_NE(full.stats().error.find("No space left on device"), std::string::npos) << full.stats().error;
    const std::vector<ToolSample> s = odd_samples(10, 1);
    EXPECT_NO_THROW(full.append(s));
    EXPECT_NO_THROW(full.sync());
    EXPECT_EQ(full.stats().records, 0u);

    JournalWriter nowhere("/nonexistent-folder/x/session.tdj", "{}");
    EXPECT_FALSE(nowhere.ok());
    EXPECT_NE(nowhere.stats().error.find("cannot create the journal"), std::string::npos) << nowhere.stats().error;
    EXPECT_NO_THROW(nowhere.append(s));
}

// Polls stats() until `done` holds or 5 s pass (the syncing thread works on its own clock).
template <class F>
bool eventually(const JournalWriter& w, F done) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (!done(w.stats())) {
        if (std::chrono::steady_clock::now() > until) return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return true;
}

TEST(Journal, SyncsWhenTheIntervalPassed) {
    const std::string path = temp_path("sync.tdj");
    const std::vector<ToolSample> s = odd_samples(3, 2);
    {
        // Interval 0: every append is a sync point; the bytes are written at once and the syncing thread makes
        // them durable without the caller calling sync().
        JournalWriter every(path, "{}", std::chrono::nanoseconds(0));
        EXPECT_EQ(every.stats().flushes, 1u);  // the header, synced by the constructor
        for (int i = 0; i < 5; ++i) every.append(s);
        EXPECT_EQ(every.stats().bytes, fs::file_size(path));  // nothing waits in the buffer
        EXPECT_TRUE(eventually(every, [&](const JournalStats& st) { return st.synced_bytes == fs::file_size(path); }));
        EXPECT_GE(every.stats().flushes, 2u);
        EXPECT_LE(every.stats().flushes, 6u);  // the syncing thread may make several appends durable at once
        EXPECT_GT(every.stats().sync_thread_ms_total, 0.0);
    }
    {
        JournalWriter rarely(path, "{}", std::chrono::hours(1));
        for (int i = 0; i < 5; ++i) rarely.append(s);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        rarely.sync_if_due();
        EXPECT_EQ(rarely.stats().flushes, 1u);  // the header only
        // Handed to the kernel within JournalWriter::kHandOffInterval (a killed process keeps them), not yet durable.
        EXPECT_EQ(rarely.stats().bytes, fs::file_size(path));
        EXPECT_LT(rarely.stats().synced_bytes, rarely.stats().bytes);
        rarely.close();
        EXPECT_EQ(rarely.stats().flushes, 2u);
        EXPECT_EQ(rarely.stats().synced_bytes, fs::file_size(path));
        EXPECT_EQ(read_journal(path).records.size(), 5u);
    }
    fs::remove(path);
}

// A sync point only writes; the fdatasync happens on the writer's own thread, within about an interval.
TEST(Journal, TheSyncingThreadMakesSyncPointsDurable) {
    const std::string path = temp_path("syncer.tdj");
    const std::vector<ToolSample> s = odd_samples(4, 5);
    JournalWriter w(path, "{}", std::chrono::milliseconds(300));
    const std::uint64_t header = w.stats().bytes;
    w.append(s);  // inside the interval: handed to the kernel at most kHandOffInterval later, not synced
    std::this_thread::sleep_for(std::chrono::milliseconds(310));
    w.sync_if_due();  // the interval passed: written out, the syncing thread woken
    EXPECT_EQ(w.stats().bytes, fs::file_size(path));
    EXPECT_GT(w.stats().bytes, header);
    EXPECT_TRUE(eventually(w, [&](const JournalStats& st) { return st.synced_bytes == st.bytes; }));
    EXPECT_GE(w.stats().flushes, 2u);  // the syncing thread may have synced the handed-off bytes on its own clock
    EXPECT_LE(w.stats().flushes, 3u);
    EXPECT_EQ(w.stats().error, "");
    EXPECT_GT(w.stats().flush_ms_total, 0.0);      // the caller's write(2)
    EXPECT_GT(w.stats().sync_thread_ms_total, 0.0);  // the syncing thread's fdatasync
    w.close();
    fs::remove(path);
}

// Appends reach the kernel within the hand-off interval, long before the sync interval makes them durable: a process
// killed then (SIGKILL, a crash) loses at most that much of its journal.
TEST(Journal, AppendsReachTheKernelWithinTheHandOffInterval) {
    const std::string path = temp_path("handoff.tdj");
    const std::vector<ToolSample> s = odd_samples(3, 7);
    JournalWriter w(path, "{}", std::chrono::hours(1));
    for (int i = 0; i < 3; ++i) {
        std::this_thread::sleep_for(JournalWriter::kHandOffInterval + std::chrono::milliseconds(2));
        w.append(s);
        EXPECT_EQ(w.stats().bytes, fs::file_size(path)) << "append " << i;
    }
    EXPECT_EQ(read_journal(path).records.size(), 3u);  // read back while the writer holds the file
    EXPECT_EQ(w.stats().flushes, 1u);                    // none made durable but the header
    w.close();
    fs::remove(path);
}

// Bytes written out because the buffer filled (no sync point since) are made durable by the syncing thread on its
// own clock, while the caller never calls sync_if_due again.
TEST(Journal, WrittenBytesBecomeDurableWithoutASyncPoint) {
    const std::string path = temp_path("fullbuf.tdj");
    const std::vector<ToolSample> s = odd_samples(100, 6);  // > 4096 bytes: the record streams through the buffer
    JournalWriter w(path, "{}", std::chrono::hours(1), 4096);  // no sync point comes; the syncer wakes every 1 s
    w.append(std::span<const ToolSample>(s).first(1));
    w.append(s);
    const std::uint64_t written = w.stats().bytes;
    EXPECT_GT(written, 4096u);
    EXPECT_TRUE(eventually(w, [&](const JournalStats& st) { return st.synced_bytes >= written; }));
    w.close();
    EXPECT_EQ(w.stats().synced_bytes, fs::file_size(path));
    EXPECT_EQ(read_journal(path).records.size(), 2u);
    fs::remove(path);
}

// Appends, sync points and stats() from one thread while the syncing thread runs (the ThreadSanitizer set runs this).
TEST(Journal, ManyAppendsWhileTheSyncingThreadRuns) {
    const std::string path = temp_path("many.tdj");
    const std::vector<ToolSample> s = odd_samples(7, 8);
    std::uint64_t appended = 0;
    {
        JournalWriter w(path, "{}", std::chrono::microseconds(300), 4096);
        const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
        while (std::chrono::steady_clock::now() < until) {
            w.append(s);
            ++appended;
            if (appended % 16 == 0) {
                w.mark(kJournalStrokeEnd, appended);
                ++appended;
                EXPECT_TRUE(w.ok());
                (void)w.stats().flushes;
            }
            std::this_thread::sleep_for(std::chrono::microseconds(50));
        }
        w.close();
        EXPECT_EQ(w.stats().error, "");
        EXPECT_EQ(w.stats().records, appended);
        EXPECT_EQ(w.stats().synced_bytes, w.stats().bytes);
        EXPECT_GE(w.stats().flushes, 3u);
    }
    const Journal j = read_journal(path);
    EXPECT_FALSE(j.cut);
    EXPECT_EQ(j.records.size(), appended);
    fs::remove(path);
}

// Stroke ends, undos, redos and checkpoints are records like batches: read back in order, with their serials, ray
// counts and file names; a flipped bit cuts the journal there; a version 1 journal cannot hold them.
TEST(Journal, MarksAndCheckpointsRoundTripAndAreCheckedLikeBatches) {
    const std::string path = temp_path("marks.tdj");
    const std::vector<ToolSample> s = odd_samples(6, 3);
    {
        JournalWriter w(path, "session");
        w.append(std::span<const ToolSample>(s).first(3));
        w.mark(kJournalStrokeEnd, 1);
        w.mark(kJournalUndo, 1, 321);
        w.mark(kJournalRedo, 1, 321);
        w.checkpoint("s.tdj.checkpoint.tdx", 4096, 0xdeadbeefu);
        w.append(std::span<const ToolSample>(s).subspan(3));
        w.mark(99, 1);  // not a mark type: ignored
        EXPECT_EQ(w.stats().records, 6u);
        EXPECT_EQ(w.stats().error, "");
    }
    const std::vector<unsigned char> bytes = file_bytes(path);
    const Journal j = parse_journal(bytes, "m.tdj");
    EXPECT_FALSE(j.cut);
    ASSERT_EQ(j.records.size(), 6u);
    EXPECT_EQ(j.version, kJournalVersion);
    EXPECT_EQ(j.records[0].kind, JournalKind::kBatch);
    EXPECT_EQ(j.records[1].kind, JournalKind::kStrokeEnd);
    EXPECT_EQ(j.records[1].serial, 1u);
    EXPECT_EQ(j.records[2].kind, JournalKind::kUndo);
    EXPECT_EQ(j.records[2].rays, 321u);
    EXPECT_EQ(j.records[3].kind, JournalKind::kRedo);
    EXPECT_EQ(j.records[4].kind, JournalKind::kCheckpoint);
    EXPECT_EQ(j.records[4].checkpoint, "s.tdj.checkpoint.tdx");
    EXPECT_EQ(j.records[4].checkpoint_bytes, 4096u);
    EXPECT_EQ(j.records[4].checkpoint_crc, 0xdeadbeefu);
    EXPECT_EQ(j.records[5].samples.size(), 3u);
    EXPECT_EQ(j.samples, 6u);

    // A bit flipped in the undo record's serial: that record is skipped, the ones after it kept.
    std::vector<unsigned char> flipped = bytes;
    flipped[j.records[2].offset + kJournalRecordHeadBytes + 8] ^= 0x04;
    const Journal f = parse_journal(flipped, "m.tdj");
    EXPECT_FALSE(f.cut);
    ASSERT_EQ(f.damage.size(), 1u);
    EXPECT_EQ(f.damage[0].record, 2u);
    EXPECT_EQ(f.damage[0].reason, "CRC mismatch");
    ASSERT_EQ(f.records.size(), j.records.size() - 1);
    EXPECT_EQ(f.records[2].kind, JournalKind::kRedo);

    // The same bytes claiming version 1 (header CRC fixed): the stroke-end record is not a version 1 record.
    std::vector<unsigned char> v1 = bytes;
    const std::uint32_t len = get_u32(v1.data() + 16);
    put_u32(v1.data() + 8, 1);
    put_u32(v1.data() + kJournalHeaderFixedBytes + len, crc32_ieee(v1.data(), kJournalHeaderFixedBytes + len));
    const Journal old = parse_journal(v1, "m.tdj");
    ASSERT_FALSE(old.damage.empty());
    EXPECT_EQ(old.damage[0].record, 1u);
    EXPECT_EQ(old.damage[0].reason, "unknown record type 2");
    fs::remove(path);
}


// One bit flipped at each of 48 positions spread evenly over a 1000-sample journal (100 records of 10 samples, seeded
// bit choice): the fraction of samples the reader keeps. Prints the median and the worst; the target is that a flip
// costs at most the damaged record, so both stay at or above 0.99.
TEST(Journal, OneBitFlipCostsAtMostTheDamagedRecord) {
    const std::string path = temp_path("flipcost.tdj");
    write_journal(path, std::vector<std::size_t>(100, 10));
    const std::vector<unsigned char> bytes = file_bytes(path);
    const Journal full = parse_journal(bytes, "full");
    ASSERT_EQ(full.samples, 1000u);
    const std::size_t first = full.records[0].offset;
    std::mt19937 rng(2024);
    std::vector<double> kept;
    constexpr int kTrials = 48;
    for (int t = 0; t < kTrials; ++t) {
        const std::size_t at = first + (bytes.size() - first) * static_cast<std::size_t>(2 * t + 1) / (2 * kTrials);
        std::vector<unsigned char> b = bytes;
        b[at] ^= static_cast<unsigned char>(1u << (rng() % 8));
        const Journal j = parse_journal(b, "flip");
        kept.push_back(static_cast<double>(j.samples) / static_cast<double>(full.samples));
    }
    std::sort(kept.begin(), kept.end());
    const double median = 0.5 * (kept[kTrials / 2 - 1] + kept[kTrials / 2]);
    std::printf("journal single-bit-flip: %d trials, samples kept median %.3f worst %.3f\n", kTrials, median, kept.front());
    EXPECT_GE(median, 0.99);
    EXPECT_GE(kept.front(), 0.99);
    fs::remove(path);
}

}  // namespace
}  // namespace tridex::compute
