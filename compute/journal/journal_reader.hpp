// compute/journal/journal_reader.hpp - reading a session journal (compute/journal/journal_format.hpp): the header
// is validated strictly, the records up to the first damaged one are kept.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/tool_sample.hpp"

namespace tridex::compute {

/// One valid record: the batch of samples one sculpt step applied.
struct JournalRecord {
    std::uint64_t offset = 0;         ///< byte offset of the record in the file
    std::vector<ToolSample> samples;  ///< in the order they were applied
};

/// Where a journal's valid prefix ends and why (a torn write, a bit flip).
struct JournalCut {
    std::uint64_t record = 0;       ///< index of the first record not kept (= the number of records kept)
    std::uint64_t byte_offset = 0;  ///< its byte offset (= the length of the valid prefix)
    std::string reason;             ///< e.g. "partial record: 96 of 1232 bytes", "CRC mismatch"
};

/// A journal read back.
struct Journal {
    std::uint32_t version = 0;           ///< format version (kJournalVersion)
    std::string session;                 ///< the session identity the writer was given
    std::vector<JournalRecord> records;  ///< every record before the first damaged one
    std::uint64_t samples = 0;           ///< samples in `records`
    std::uint64_t file_bytes = 0;        ///< size of the input
    std::optional<JournalCut> cut;       ///< set when bytes after the last valid record were dropped
};

/// Parses journal bytes. The header must be complete and intact: throws tridex::Error "<where>: <what>" when it
/// is not a journal (magic), is another version ("journal version 2; this build reads version 1"), has another
/// sample size, or is truncated or damaged (CRC). Records are kept up to the first that is incomplete, fails its
/// CRC, has an unknown type, a wrong length or record index, or a sample field no writer writes; the rest is
/// reported in Journal::cut. O(file size).
Journal parse_journal(std::span<const unsigned char> bytes, const std::string& where);

/// Reads and parses the journal file at `path` (parse_journal). Throws tridex::Error "<path>: cannot read" too.
Journal read_journal(const std::string& path);

}  // namespace tridex::compute
