// compute/model/tdx_file.hpp - the model file (.tdx): the whole tri-dexel model, its workpiece transform and the
// session settings that made it, saved and loaded bit for bit (DESIGN.md, persistence).
//
// Layout (little-endian):
//   header, 40 bytes: magic "TDXMODEL", u32 format version, u32 flags (0), u32 section count, u32 0,
//                     u64 file size, u32 CRC-32 of bytes 0..31, u32 0
//   sections, in this order, each a 32-byte header - u32 id, u32 CRC-32 of the uncompressed payload,
//   u64 uncompressed size, u64 compressed size, u32 CRC-32 of the compressed bytes, u32 CRC-32 of the header's
//   bytes 0..27 - and its payload compressed as one zstd frame (the compressed bytes are checked before zstd
//   reads them: a zstd frame can carry bits it ignores):
//     1 meta      lattice, transform (input mesh units -> world m), intervals per ray set (tdx_codec.hpp)
//     2 settings  the caller's JSON text (opaque here)
//     3 rays.x, 4 rays.y, 5 rays.z   each ray set's interval counts, depths and materials
//     6 tiles     the tile grid's dirty flags
//     7 palette   the materials' names and colours (tdx_palette.hpp); version 2 only, written when the palette is
//                 not the default (a default palette is saved as version 1, which every reader reads)
// The CPU TriDexel holds every interval (the GPU model's spill pool is copied back into it), so nothing else
// is needed to restore a session's model.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "compute/model/tridexel.hpp"
#include "core/material_palette.hpp"
#include "core/math.hpp"
#include "core/progress.hpp"

namespace tridex::compute {

inline constexpr char kTdxMagic[8] = {'T', 'D', 'X', 'M', 'O', 'D', 'E', 'L'};  ///< first 8 bytes of a .tdx
/// The newest format version this build reads and writes: 1 (six sections, the default palette) or 2 (a seventh,
/// the palette). save_tdx writes 1 when the palette is the default, so older readers still read those files.
inline constexpr std::uint32_t kTdxVersion = 2;

/// A model file's contents.
struct TdxModel {
    TriDexel model;             ///< the tri-dexel solid, with its tile grid's dirty flags
    Mat4 to_world{1.0};         ///< workpiece transform: input mesh units -> world m
    std::string settings_json;  ///< the session settings given to save_tdx (opaque to compute)
    MaterialPalette palette = default_material_palette();  ///< materials' names and colours (default for version 1)
};

/// Writes `model`, `to_world`, `settings_json` and `palette` (version 2 unless it is the default) to `path` as a
/// .tdx file: to "<path>.tmp-<pid>", flushed and
/// fsync'ed, then renamed over `path` (core/atomic_file.hpp), so a crash or a full disk during a save leaves
/// the previous file as it was. zstd level `level` (1..19). Throws tridex::Error "<path>: ..." on any failed
/// write or a model whose interval counts exceed 2^32 - 1 per ray.
void save_tdx(const std::string& path, const TriDexel& model, const Mat4& to_world, const std::string& settings_json,
              int level = 3, const MaterialPalette& palette = default_material_palette());

/// Reads a .tdx file, checking everything before trusting it: magic, version (newer ones refused), flags, the
/// header's and each section's CRC-32, sizes against the file size and against what the lattice allows (no
/// allocation larger than the model the lattice can hold, and none above `max_bytes` for the model), the
/// zstd frames, and every interval (finite, ordered, within the lattice). load_tdx(save_tdx(m)) equals m bit
/// for bit. Throws tridex::Error "<path>: <what is wrong>" (e.g. "m.tdx: checksum mismatch in section
/// 'rays.y'", "m.tdx: truncated: section 4 ('rays.y') needs 1200 bytes at offset 5000, the file has 5100").
/// `progress` (core/progress.hpp) hears the fraction of the file read after each section.
TdxModel load_tdx(const std::string& path, std::size_t max_bytes, const ProgressFn& progress = {});

/// The palette of a .tdx file alone (the default for a version 1 file), its header and palette section checked as
/// load_tdx checks them, the other sections skipped: for a scene that names a saved model's materials before the
/// model is loaded. Throws tridex::Error "<path>: ..." as load_tdx does.
MaterialPalette load_tdx_palette(const std::string& path);

}  // namespace tridex::compute
