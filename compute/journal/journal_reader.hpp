// compute/journal/journal_reader.hpp - reading a session journal (compute/journal/journal_format.hpp): the header
// is validated strictly; a damaged record is skipped and reading resumes at the next intact one.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/tool_sample.hpp"

namespace tridex::compute {

/// What a journal record is (journal_format.hpp's record types).
enum class JournalKind : std::uint8_t {
    kBatch = 1,       ///< samples applied as one batch
    kStrokeEnd = 2,   ///< the open stroke closed
    kUndo = 3,        ///< a stroke undone
    kRedo = 4,        ///< a stroke redone
    kCheckpoint = 5,  ///< a checkpoint model file holds the model as of this record
    kIntake = 6,      ///< samples received before the sculpt thread applied them (parse_journal moves them to the tail)
    kLattice = 7,     ///< the model re-sampled onto another lattice (its coarseness changed), as one undo step
};

/// One valid record.
struct JournalRecord {
    JournalKind kind = JournalKind::kBatch;
    std::uint64_t offset = 0;         ///< byte offset of the record in the file
    std::uint64_t index = 0;          ///< its record index (0, 1, ...; a gap before it: damaged records skipped)
    std::vector<ToolSample> samples;  ///< kBatch: in the order they were applied; else empty
    /// A kBatch parse_journal made, after every record read, of the intake samples no batch record holds (samples
    /// the session received and had not applied when its journal ended); applied as the sculpt thread would have.
    bool tail = false;
    std::uint64_t seq = 0;            ///< kIntake: the sequence number of its first sample (samples moved to the tail)
    std::uint64_t serial = 0;         ///< kStrokeEnd, kUndo, kRedo, kLattice: the step's serial (UndoHistory)
    std::uint64_t rays = 0;           ///< kUndo, kRedo: rays written back; kLattice: the new resolution
    std::string checkpoint;           ///< kCheckpoint: the model file's name (in the journal's folder)
    std::uint64_t checkpoint_bytes = 0;  ///< kCheckpoint: its size, bytes
    std::uint32_t checkpoint_crc = 0;    ///< kCheckpoint: its CRC-32 (crc32_ieee of the whole file)
};

/// Where a journal's valid prefix ends and why (a torn write, a bit flip).
struct JournalCut {
    std::uint64_t record = 0;       ///< record index of the first record not kept
    std::uint64_t byte_offset = 0;  ///< its byte offset (= the length of the valid prefix)
    std::string reason;             ///< e.g. "partial record: 96 of 1232 bytes", "CRC mismatch"
};

/// A damaged stretch the reader skipped before resynchronising at the next intact record.
struct JournalDamage {
    std::uint64_t record = 0;       ///< index of the first record lost (= the records kept before it)
    std::uint64_t byte_offset = 0;  ///< where the damaged stretch starts
    std::uint64_t bytes = 0;        ///< its length, bytes
    std::uint64_t records_lost = 0; ///< records it held, from the gap in record indices
    std::uint64_t samples_lost = 0; ///< samples it held, estimated as bytes / kJournalSampleBytes
    std::string reason;             ///< why its first record was refused, as in JournalCut::reason
};

/// A journal read back.
struct Journal {
    std::uint32_t version = 0;           ///< format version (kJournalOldestVersion..kJournalVersion)
    std::string session;                 ///< the session identity the writer was given
    std::vector<JournalRecord> records;  ///< every intact record, in file order
    std::uint64_t samples = 0;           ///< samples in `records` (batches and the tail)
    std::uint64_t intake_samples = 0;    ///< samples the intake records held (most also in batch records)
    std::uint64_t tail_samples = 0;      ///< of those, the tail's: received, never applied, applied by a replay
    /// After damage (0 without): intake samples numbered past the batches' samples and the damaged stretches'
    /// estimated ones (JournalDamage::samples_lost), so received and perhaps never applied; not replayed, since the
    /// damage leaves their place in the stream unknown. An under-count when a damaged stretch held more than site-0
    /// batch samples (an intake record, another site's samples): the estimate then places too many.
    std::uint64_t tail_unplaced = 0;
    std::uint64_t file_bytes = 0;        ///< size of the input
    std::optional<JournalCut> cut;       ///< set when the file ends in damage no intact record follows
    std::vector<JournalDamage> damage;   ///< damaged stretches followed by an intact record, in file order
};

/// Parses journal bytes. The header must be complete and intact: throws tridex::Error "<where>: <what>" when it
/// is not a journal (magic), is another version ("journal version 3; this build reads versions 1 to 2"), has another
/// sample size, or is truncated or damaged (CRC). Records are kept up to the first that is incomplete, fails its
/// CRC, has an unknown type (or a mark in a version 1 journal), a wrong length or record index, a checkpoint name
/// that is empty, too long or holds a '/', or a sample field no writer writes (an impossible tool kind or op, a
/// non-finite time, pose or tool size, a negative tool size, a material id over kMaxMaterialId). Such a record
/// is skipped: the reader scans forward byte by byte for the next offset holding a record that passes every check
/// above with a record index above the last kept one (type, length and index are the sync pattern, the CRC-32
/// confirms it), resumes there and reports the skipped stretch in Journal::damage; with no intact record after
/// it, the rest is reported in Journal::cut. O(file size) for a clean journal; a damaged stretch costs one CRC per
/// candidate offset whose head looks like a record's. Intake records (version 4) are kept with their samples moved:
/// those that follow the batch records' samples without a gap (by sequence number) become one last kBatch record
/// marked `tail`, indexed after the last record read; with damage in the journal there is no tail.
Journal parse_journal(std::span<const unsigned char> bytes, const std::string& where);

/// Reads and parses the journal file at `path` (parse_journal). Throws tridex::Error "<path>: cannot read" too.
Journal read_journal(const std::string& path);

}  // namespace tridex::compute
