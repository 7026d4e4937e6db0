// The host's stream log: records read back from any point equal those appended, across packed chunks and the
// unpacked tail, and the packed log holds a fraction of the records' own bytes.
#include <gtest/gtest.h>

#include <cstdio>

#include "app/session/shared/record_log.hpp"
#include "compute/journal/journal_format.hpp"

namespace tridex::app {
namespace {

// Record k of a scripted stream: mostly batches of a tool moving along a groove, a stroke end every 50.
compute::JournalRecord record(std::size_t k) {
    compute::JournalRecord r;
    r.index = k;
    if (k % 50 == 49) {
        r.kind = compute::JournalKind::kStrokeEnd;
        r.serial = k / 50 + 1;
        return r;
    }
    r.kind = compute::JournalKind::kBatch;
    for (int i = 0; i < 4; ++i) {
        ToolSample s;
        s.t_s = 1e-3 * static_cast<double>(4 * k + i);
        s.position = Vec3(0.01 * std::sin(s.t_s), 0.02, 0.04 + 1e-4 * i);
        s.tool.radius_m = 0.004;
        s.op = ToolOp::kSubtract;
        r.samples.push_back(s);
    }
    return r;
}

bool same(const compute::JournalRecord& a, const compute::JournalRecord& b) {
    if (a.index != b.index || a.kind != b.kind || a.serial != b.serial || a.samples.size() != b.samples.size()) return false;
    for (std::size_t i = 0; i < a.samples.size(); ++i)
        if (a.samples[i].position != b.samples[i].position || a.samples[i].t_s != b.samples[i].t_s) return false;
    return true;
}

TEST(RecordLog, RecordsReadBackFromAnyPointEqualThoseAppended) {
    RecordLog log;
    const std::size_t n = 3 * RecordLog::kChunkRecords + 300;
    std::vector<compute::JournalRecord> batch;
    for (std::size_t k = 0; k < n; ++k) {  // appended in uneven pieces, as frames take them
        batch.push_back(record(k));
        if (batch.size() == 1 + k % 37 || k + 1 == n) {
            log.append(std::move(batch));
            batch.clear();
        }
    }
    ASSERT_EQ(log.size(), n);
    for (const std::size_t from : {std::size_t{0}, std::size_t{1}, RecordLog::kChunkRecords - 1,
                                   RecordLog::kChunkRecords, 2 * RecordLog::kChunkRecords + 500, n - 300, n - 1}) {
        const std::vector<compute::JournalRecord> got = log.read(from, 2000);
        ASSERT_EQ(got.size(), std::min<std::size_t>(2000, n - from)) << from;
        for (std::size_t i = 0; i < got.size(); ++i) ASSERT_TRUE(same(got[i], record(from + i))) << from + i;
    }
    EXPECT_TRUE(log.read(n, 10).empty());
    std::size_t plain = 0;
    for (std::size_t k = 0; k < n; ++k) plain += sizeof(compute::JournalRecord) + record(k).samples.size() * sizeof(ToolSample);
    std::printf("%zu records: %zu bytes packed, %zu as they are (%.1fx)\n", n, log.bytes(), plain,
                static_cast<double>(plain) / static_cast<double>(log.bytes()));
    EXPECT_LT(log.bytes(), plain / 2) << "the packed log is not smaller";
}

}  // namespace
}  // namespace tridex::app
