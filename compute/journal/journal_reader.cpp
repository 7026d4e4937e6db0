// compute/journal/journal_reader.cpp - the session journal's validating reader.
#include "compute/journal/journal_reader.hpp"

#include <cstring>
#include <fstream>
#include <iterator>

#include "compute/journal/journal_format.hpp"
#include "core/crc32.hpp"
#include "core/error.hpp"

namespace tridex::compute {

namespace {

// Checks the record at `off`; on success fills `rec` and returns "" and the record's total size in `size`.
std::string check_record(std::span<const unsigned char> b, std::uint64_t off, std::uint64_t index, JournalRecord& rec,
                         std::uint64_t& size) {
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
    if (type != kJournalBatch) return "unknown record type " + std::to_string(type);
    const unsigned char* q = p + kJournalRecordHeadBytes;
    if (payload < kJournalBatchHeadBytes) return "record too short for a batch";
    const std::uint32_t count = get_u32(q + 8);
    if (payload != kJournalBatchHeadBytes + std::uint64_t{count} * kJournalSampleBytes)
        return "batch length does not match its " + std::to_string(count) + " samples";
    if (get_u64(q) != index) return "record index " + std::to_string(get_u64(q)) + " where " + std::to_string(index) + " belongs";
    if (get_u32(q + 12) != 0) return "reserved field set";
    rec.offset = off;
    rec.samples.resize(count);
    for (std::uint32_t i = 0; i < count; ++i)
        if (!decode_sample(q + kJournalBatchHeadBytes + std::size_t{i} * kJournalSampleBytes, rec.samples[i]))
            return "sample " + std::to_string(i) + " holds an impossible tool kind or op";
    return "";
}

}  // namespace

Journal parse_journal(std::span<const unsigned char> b, const std::string& where) {
    Journal j;
    j.file_bytes = b.size();
    if (b.size() < 8 || std::memcmp(b.data(), kJournalMagic, 8) != 0)
        throw Error(where + ": not a tridex session journal (no TRDXJNL header)");
    if (b.size() < kJournalHeaderFixedBytes) throw Error(where + ": the journal header is truncated");
    j.version = get_u32(b.data() + 8);
    if (j.version != kJournalVersion)
        throw Error(where + ": journal version " + std::to_string(j.version) + "; this build reads version " +
                    std::to_string(kJournalVersion));
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
    while (off < b.size()) {
        JournalRecord rec;
        std::uint64_t size = 0;
        const std::string why = check_record(b, off, j.records.size(), rec, size);
        if (!why.empty()) {
            j.cut = JournalCut{j.records.size(), off, why};
            break;
        }
        j.samples += rec.samples.size();
        j.records.push_back(std::move(rec));
        off += size;
    }
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
