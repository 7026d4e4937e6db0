// compute/journal/journal_reader.cpp - the session journal's validating reader.
#include "compute/journal/journal_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "compute/journal/journal_format.hpp"
#include "core/crc32.hpp"
#include "core/error.hpp"
#include "core/format.hpp"

namespace tridex::compute {

namespace {

// What is wrong with a decoded sample that a session could not have written ("" when nothing): non-finite time,
// pose or tool size, a negative tool size, or a material outside the palette.
std::string sample_problem(const ToolSample& s) {
    if (!std::isfinite(s.t_s)) return "t_s = " + format_number(s.t_s) + " is not finite";
    if (!is_finite(s.position)) return "position is not finite";
    const Quat& q = s.orientation;
    if (!(std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)))
        return "orientation is not finite";
    if (!(std::isfinite(s.tool.radius_m) && s.tool.radius_m >= 0.0))
        return "tool.radius_m = " + format_number(s.tool.radius_m) + " must be finite and >= 0";
    if (!(std::isfinite(s.tool.length_m) && s.tool.length_m >= 0.0))
        return "tool.length_m = " + format_number(s.tool.length_m) + " must be finite and >= 0";
    if (s.material > kMaxMaterialId)
        return "material = " + std::to_string(s.material) + " is not a material id (0.." +
               std::to_string(kMaxMaterialId) + ")";
    return "";
}

// Checks the record at `off`; on success fills `rec` and returns "" and the record's total size in `size`.
// `index` is the record index expected; any index in [index, last_index] passes too (after a damaged stretch).
std::string check_record(std::span<const unsigned char> b, std::uint64_t off, std::uint64_t index, std::uint32_t version,
                         JournalRecord& rec, std::uint64_t& size, std::uint64_t last_index = 0) {
    const std::uint64_t left = b.size() - off;
    const unsigned char* p = b.data() + off;
    if (left < kJournalRecordHeadBytes)
        return "partial record: " + std::to_string(left) + " bytes, shorter than a record head";
    const std::uint32_t type = get_u32(p), payload = get_u32(p + 4);
    if (payload > kJournalMaxPayloadBytes) return "record length " + std::to_string(payload) + " is out of range";
    size = kJournalRecordHeadBytes + std::uint64_t{payload} + 4;
    if (left < size) return "partial record: " + std::to_string(left) + " of " + std::to_string(size) + " bytes";
    if (crc32_ieee(p, kJournalRecordHeadBytes + payload) != get_u32(p + kJournalRecordHeadBytes + payload))
        return "CRC mismatch";
    const unsigned char* q = p + kJournalRecordHeadBytes;
    if (type < kJournalBatch || type > kJournalLattice || (version < 2 && type != kJournalBatch) ||
        (version < 4 && type == kJournalIntake) || (version < 6 && type == kJournalLattice))
        return "unknown record type " + std::to_string(type);
    if (payload < 8) return "record too short";
    if (get_u64(q) < index || get_u64(q) > std::max(index, last_index))
        return "record index " + std::to_string(get_u64(q)) + " where " + std::to_string(index) + " belongs";
    rec.offset = off;
    rec.index = get_u64(q);
    rec.kind = static_cast<JournalKind>(type);
    if (type == kJournalStrokeEnd || type == kJournalUndo || type == kJournalRedo || type == kJournalLattice) {
        if (payload != kJournalMarkBytes) return "mark record of " + std::to_string(payload) + " bytes";
        rec.serial = get_u64(q + 8);
        rec.rays = get_u64(q + 16);
        if (rec.serial == 0) return "mark of stroke 0";
        return "";
    }
    if (type == kJournalCheckpoint) {
        if (payload < kJournalCheckpointHeadBytes) return "checkpoint record too short";
        const std::uint32_t n = get_u32(q + 20);
        if (n == 0 || n > kJournalMaxNameBytes || payload != kJournalCheckpointHeadBytes + std::uint64_t{n})
            return "checkpoint name length " + std::to_string(n) + " does not fit the record";
        rec.checkpoint_bytes = get_u64(q + 8);
        rec.checkpoint_crc = get_u32(q + 16);
        rec.checkpoint.assign(reinterpret_cast<const char*>(q + kJournalCheckpointHeadBytes), n);
        if (rec.checkpoint.find('/') != std::string::npos || rec.checkpoint.find('\0') != std::string::npos ||
            rec.checkpoint == "." || rec.checkpoint == "..")
            return "checkpoint name is not a plain file name";
        return "";
    }
    const std::size_t head = type == kJournalIntake ? kJournalIntakeHeadBytes : kJournalBatchHeadBytes;
    if (payload < head) return type == kJournalIntake ? "record too short for intake" : "record too short for a batch";
    const std::uint32_t count = get_u32(q + 8);
    if (payload != head + std::uint64_t{count} * kJournalSampleBytes)
        return "batch length does not match its " + std::to_string(count) + " samples";
    if (get_u32(q + 12) != 0) return "reserved field set";
    if (type == kJournalIntake) {
        rec.seq = get_u64(q + 16);
        if (rec.seq > std::numeric_limits<std::uint64_t>::max() - count) return "intake sequence number out of range";
    }
    rec.samples.resize(count);
    for (std::uint32_t i = 0; i < count; ++i)
    {
        if (!decode_sample(q + head + std::size_t{i} * kJournalSampleBytes, rec.samples[i]))
            return "sample " + std::to_string(i) + " holds an impossible tool kind or op";
        const std::string bad = sample_problem(rec.samples[i]);
        if (!bad.empty()) return "sample " + std::to_string(i) + ": " + bad;
    }
    return "";
}

// The intake samples that follow the batches' samples without a gap (journal_format.hpp, kJournalIntake), moved
// out of the intake records into one batch record after the last record, marked as the tail. Not after damage:
// the batches' sample count, which numbers the samples, is then unknown.
void take_tail(Journal& j) {
    std::uint64_t applied = 0;
    bool any_intake = false;
    for (const JournalRecord& r : j.records) {
        if (r.kind == JournalKind::kBatch)
            for (const ToolSample& x : r.samples) applied += x.site == 0;  // intake numbers site 0's samples only
        any_intake |= r.kind == JournalKind::kIntake;
    }
    if (!any_intake) return;
    JournalRecord tail;
    tail.kind = JournalKind::kBatch;
    tail.tail = true;
    std::uint64_t next = applied;  // the sequence number the tail needs next
    const bool damaged = !j.damage.empty();
    bool gap = damaged;
    // After damage, the intake samples numbered past every batch sample, the lost ones counted by their estimate (an
    // upper bound on the batch samples lost; the highest end counted so far, so that overlaps count once).
    std::uint64_t placed = applied;
    for (const JournalDamage& d : j.damage) placed += d.samples_lost;
    for (JournalRecord& r : j.records) {
        if (r.kind != JournalKind::kIntake) continue;
        const std::uint64_t end = r.seq + r.samples.size();
        if (damaged && end > placed) {
            j.tail_unplaced += end - std::max<std::uint64_t>(r.seq, placed);
            placed = end;
        }
        for (std::size_t i = 0; i < r.samples.size() && !gap; ++i) {
            const std::uint64_t seq = r.seq + i;
            if (seq < next) continue;
            if (seq > next) {
                gap = true;
                break;
            }
            tail.samples.push_back(r.samples[i]);
            ++next;
        }
        j.intake_samples += r.samples.size();
        r.samples.clear();  // an intake record applies nothing itself
    }
    j.samples -= j.intake_samples;
    if (tail.samples.empty()) return;
    tail.index = j.records.back().index + 1;
    tail.offset = j.records.back().offset;
    j.tail_samples = tail.samples.size();
    j.samples += j.tail_samples;
    j.records.push_back(std::move(tail));
}

}  // namespace

Journal parse_journal(std::span<const unsigned char> b, const std::string& where) {
    Journal j;
    j.file_bytes = b.size();
    if (b.size() < 8 || std::memcmp(b.data(), kJournalMagic, 8) != 0)
        throw Error(where + ": not a tridex session journal (no TRDXJNL header)");
    if (b.size() < kJournalHeaderFixedBytes) throw Error(where + ": the journal header is truncated");
    j.version = get_u32(b.data() + 8);
    if (j.version < kJournalOldestVersion || j.version > kJournalVersion)
        throw Error(where + ": journal version " + std::to_string(j.version) + "; this build reads versions " +
                    std::to_string(kJournalOldestVersion) + " to " + std::to_string(kJournalVersion));
    const std::uint32_t sample_bytes = get_u32(b.data() + 12), len = get_u32(b.data() + 16);
    if (len > kJournalMaxSessionBytes || b.size() < kJournalHeaderFixedBytes + std::uint64_t{len} + 4)
        throw Error(where + ": the journal header is truncated or damaged");
    if (crc32_ieee(b.data(), kJournalHeaderFixedBytes + len) != get_u32(b.data() + kJournalHeaderFixedBytes + len))
        throw Error(where + ": the journal header is damaged (CRC mismatch)");
    if (sample_bytes != kJournalSampleBytes)
        throw Error(where + ": journal samples of " + std::to_string(sample_bytes) + " bytes; this build reads " +
                    std::to_string(kJournalSampleBytes));
    j.session.assign(reinterpret_cast<const char*>(b.data() + kJournalHeaderFixedBytes), len);
    std::uint64_t off = kJournalHeaderFixedBytes + std::uint64_t{len} + 4;
    std::uint64_t index = 0;  // the record index the next record carries
    // The smallest record on disk (an empty batch), bounding how many records a damaged stretch can hold.
    constexpr std::uint64_t kMinRecord = kJournalRecordHeadBytes + kJournalBatchHeadBytes + 4;
    while (off < b.size()) {
        JournalRecord rec;
        std::uint64_t size = 0;
        const std::string why = check_record(b, off, index, j.version, rec, size);
        if (!why.empty()) {
            // Resynchronise: the next offset whose bytes hold an intact record with a later index.
            std::uint64_t next = off + 1;
            for (; next + kJournalRecordHeadBytes <= b.size(); ++next) {
                const unsigned char* p = b.data() + next;
                if (p[0] < kJournalBatch || p[0] > kJournalIntake || p[1] != 0 || p[2] != 0 || p[3] != 0) continue;
                JournalRecord probe;
                std::uint64_t probe_size = 0;
                const std::uint64_t last = index + (next - off) / kMinRecord;
                // Cheap tests first (the index must fit the gap), the CRC over the payload only then.
                if (next + kJournalRecordHeadBytes + 8 > b.size()) continue;
                const std::uint64_t at = get_u64(p + kJournalRecordHeadBytes);
                if (at < index || at > last) continue;
                if (check_record(b, next, index, j.version, probe, probe_size, last).empty()) break;
            }
            if (next + kJournalRecordHeadBytes > b.size()) {
                j.cut = JournalCut{index, off, why};
                break;
            }
            const std::uint64_t found = get_u64(b.data() + next + kJournalRecordHeadBytes);
            j.damage.push_back(
                JournalDamage{index, off, next - off, found - index, (next - off) / kJournalSampleBytes, why});
            index = found;
            off = next;
            continue;
        }
        ++index;
        j.samples += rec.samples.size();
        j.records.push_back(std::move(rec));
        off += size;
    }
    take_tail(j);
    return j;
}

Journal read_journal(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot read");
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw Error(path + ": cannot read");
    return parse_journal(bytes, path);
}

}  // namespace tridex::compute
