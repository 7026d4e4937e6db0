// The sculpt thread's record stream handed to another thread (a cluster's frame loop): every record once, in order,
// indices 0, 1, ...; a digest asked for is taken on the feeding thread and placed after the record it follows (at
// 0 when that record went out with the previous take).
// Run under ThreadSanitizer by .ci/run.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "compute/journal/journal_format.hpp"
#include "compute/journal/stream_buffer.hpp"
#include "compute/model/lattice.hpp"
#include "compute/model/model_digest.hpp"

namespace tridex::compute {
namespace {

TEST(StreamBuffer, RecordsCrossThreadsOnceAndInOrder) {
    TriDexel model = TriDexel::empty(Lattice::around(Aabb{Vec3(-0.05), Vec3(0.05)}, 16), std::size_t{1} << 30);
    model.sets[2].rays[5].push_back(Interval{0.01f, 0.02f, 0, 0});
    ToolStreamBuffer stream;
    constexpr int kBatches = 2000;
    // The feeding thread starts once a digest has been asked for, so at least one is taken however the two threads
    // are scheduled (it could otherwise feed every record before the first request).
    std::atomic<bool> go{false};
    std::thread sculpt([&] {
        while (!go.load()) std::this_thread::yield();
        std::vector<ToolSample> s(3);
        for (int i = 0; i < kBatches; ++i) {
            stream.append(s);
            stream.after_record(model);
            if (i % 100 == 99) {
                stream.mark(kJournalStrokeEnd, static_cast<std::uint64_t>(i / 100 + 1), 0);
                stream.after_record(model);
            }
        }
    });
    std::vector<JournalRecord> got;
    std::size_t checks = 0;
    stream.request_digest();
    go.store(true);
    while (got.size() < kBatches + kBatches / 100) {
        stream.request_digest();
        ToolStreamBuffer::Taken t = stream.take();
        if (t.digest) {
            ++checks;
            EXPECT_EQ(*t.digest, model_digest(model));
            EXPECT_LE(t.digest_after, t.records.size());
        }
        for (JournalRecord& r : t.records) got.push_back(std::move(r));
        std::this_thread::yield();
    }
    sculpt.join();
    for (std::size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i].index, i);
    EXPECT_EQ(got[99].kind, JournalKind::kBatch);
    EXPECT_EQ(got[100].kind, JournalKind::kStrokeEnd);
    EXPECT_EQ(got[100].serial, 1u);
    EXPECT_EQ(stream.records(), got.size());
    EXPECT_GT(checks, 0u);
}

}  // namespace
}  // namespace tridex::compute
