// compute/journal/journal_format.hpp - the session journal's binary format ("TRDXJNL"): constants and the
// bit-exact encoding of one ToolSample. The journal is the ToolSample stream the sculpt thread applied, which
// determines the model (DESIGN.md, persistence).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/le_bytes.hpp"  // put_u32, get_u32, ... for the journal's integers
#include "core/tool_sample.hpp"

namespace tridex::compute {

// ---- File layout (all integers and floats little-endian; floats IEEE-754 binary64, copied bit for bit) -------
// Header:
//    0 magic "TRDXJNL\0" (8 bytes) | 8 version u32 | 12 sample bytes u32 (kJournalSampleBytes)
//   16 session length L u32 | 20 session identity, L bytes (opaque to compute; the app's SessionSpec JSON)
//   20+L CRC-32 (crc32_ieee) u32 of bytes [0, 20+L)
// Then records, back to back, each:
//    0 type u32 (kJournalBatch) | 4 payload length P u32 | 8 payload, P bytes | 8+P CRC-32 u32 of bytes [0, 8+P)
// kJournalBatch payload: 0 record index u64 (0, 1, 2, ... in file order) | 8 sample count N u32 | 12 reserved u32 (0)
//   | 16 N samples of kJournalSampleBytes each, in the order the sculpt thread drained and applied them, one
//   record per application (the samples of one sculpt step, split where a stroke ends inside it).
// kJournalStrokeEnd / kJournalUndo / kJournalRedo payload (marks): 0 record index u64 | 8 stroke serial u64
//   | 16 rays u64 (undo, redo: rays written back; stroke end: 0). A stroke end closes the open stroke (its serial);
//   an undo or redo closes it too, then restores or re-applies the stroke with that serial (UndoHistory).
// kJournalLattice payload (version 6; a mark): 0 record index u64 | 8 step serial u64 | 16 resolution u64: the model
//   was re-sampled onto a lattice of that many cells along its longest side (app::SculptHistory::resample), as one
//   undo step with that serial, after closing the open stroke. An undo or redo of that serial swaps the lattices
//   back or forth; its rays field is then the ray count of the model after it.
// kJournalCheckpoint payload: 0 record index u64 | 8 model bytes u64 | 16 model CRC-32 u32 | 20 name length N u32
//   | 24 N bytes: the checkpoint model file (.tdx) next to the journal, by file name, holding the model after every
//   record before this one.
// kJournalIntake payload (version 4): 0 record index u64 | 8 sample count N u32 | 12 reserved u32 (0) | 16 sequence
//   number u64 of the first sample (the samples the haptic loop handed the sculpt thread, numbered 0, 1, ... in the
//   order it drains them: the session's own tool's, site 0; other sites' samples reach the sculpt thread another way
//   and are kept by batch records only, so the batches' site-0 samples are what the numbers count) | 24 N samples. Written as samples leave the haptic loop, by the journal's intake thread,
//   for those no batch record holds yet: a session killed while the sculpt thread is behind keeps them. Readers
//   apply, after the last record, the intake samples that follow the batches' samples without a gap.
// Sample (120 bytes): 0 t_s f64 | 8 position xyz f64 | 32 surface_m xyz f64 | 56 orientation w x y z f64
//   | 88 tool.radius_m f64 | 96 tool.length_m f64 | 104 tool.mesh_id u32 | 108 buttons u32 | 112 tool.kind u8
//   | 113 op u8 | 114 material u8 | 115 symmetry u8: mirror planes in bits 0..2 (x, y, z), radial axis in bits 4..5
//   (0 x, 1 y, 2 z), bits 3, 6, 7 zero | 116 radial copies u16 (0 = none, else 2..32; then no mirror bits)
//   (core/symmetry.hpp; versions 1 and 2 wrote zeros there: no symmetry) | 118 site u8 (0..kMaxSites-1: whose tool
//   made the sample; versions 1 to 4 wrote a u32 radial count at 116, so zeros here: site 0) | 119 zero
// ---------------------------------------------------------------------------------------------------------

inline constexpr char kJournalMagic[8] = {'T', 'R', 'D', 'X', 'J', 'N', 'L', '\0'};  ///< first 8 bytes
/// The version this build writes (and reads, with 1 to 3). 3: samples carry their symmetry (bytes 115, 116), so a
/// reader of version 2, which would ignore it and build another model, refuses the file. 4: intake records
/// (kJournalIntake), whose samples a version 3 reader would not apply. 5: samples carry their site (byte 118), so a
/// reader of version 4, which would join the sweeps of two sites' tools, refuses the file. 6: lattice records
/// (kJournalLattice), which change the model's coarseness.
inline constexpr std::uint32_t kJournalVersion = 6;
inline constexpr std::uint32_t kJournalOldestVersion = 1;    ///< oldest version this build reads (batches only)
inline constexpr std::size_t kJournalSampleBytes = 120;      ///< bytes per ToolSample on disk
inline constexpr std::size_t kJournalHeaderFixedBytes = 20;  ///< header bytes before the session identity
inline constexpr std::size_t kJournalRecordHeadBytes = 8;    ///< type + payload length
inline constexpr std::size_t kJournalBatchHeadBytes = 16;    ///< record index + count + reserved
inline constexpr std::uint32_t kJournalBatch = 1;            ///< record type: one sculpt step's batch of samples
inline constexpr std::uint32_t kJournalStrokeEnd = 2;        ///< record type: the open stroke closed
inline constexpr std::uint32_t kJournalUndo = 3;             ///< record type: a stroke undone
inline constexpr std::uint32_t kJournalRedo = 4;             ///< record type: a stroke redone
inline constexpr std::uint32_t kJournalCheckpoint = 5;       ///< record type: a checkpoint model was written
inline constexpr std::uint32_t kJournalIntake = 6;           ///< record type: samples received, not yet applied
inline constexpr std::uint32_t kJournalLattice = 7;          ///< record type: the model re-sampled (coarseness)
inline constexpr std::size_t kJournalIntakeHeadBytes = 24;   ///< intake payload before its samples
inline constexpr std::size_t kJournalMarkBytes = 24;         ///< payload of a stroke-end, undo, redo or lattice record
inline constexpr std::size_t kJournalCheckpointHeadBytes = 24;  ///< checkpoint payload before the file name
inline constexpr std::uint32_t kJournalMaxNameBytes = 4096;  ///< longest checkpoint file name a reader accepts
/// Largest session identity and record payload a reader accepts, bytes (a longer length field is damage).
inline constexpr std::uint32_t kJournalMaxSessionBytes = 16u << 20;
inline constexpr std::uint32_t kJournalMaxPayloadBytes = 256u << 20;

/// Writes `s` into out[0, kJournalSampleBytes) in the layout above (bit-exact doubles).
void encode_sample(const ToolSample& s, unsigned char* out);

/// Reads a sample written by encode_sample from in[0, kJournalSampleBytes). False (out unspecified) when the
/// tool kind, op or symmetry bytes hold values encode_sample never writes.
bool decode_sample(const unsigned char* in, ToolSample& out);

}  // namespace tridex::compute
