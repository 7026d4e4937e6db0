// compute/model/tdx_codec.hpp - the uncompressed payloads of a .tdx model file's sections (tdx_file.hpp): the
// lattice and transform ("meta"), one ray set ("rays.x/y/z") and the tile grid ("tiles"), each encoded to bytes
// and decoded with every value checked. Little-endian, no padding.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "compute/model/tridexel.hpp"
#include "core/math.hpp"

namespace tridex::compute::tdx {

using Bytes = std::vector<unsigned char>;

/// What the "meta" section holds: the lattice, the workpiece transform and the interval count per ray set.
struct Meta {
    Lattice lattice;
    Mat4 to_world{1.0};                     ///< input mesh units -> world m
    std::array<std::uint64_t, 3> intervals{};  ///< intervals in rays.x, rays.y, rays.z
};

/// Bytes of an encoded Meta: origin (3 f64, m), cell (f64, m), cells (3 i32), tile cells (i32), to_world (16
/// f64, glm's column-major order), intervals (3 u64).
inline constexpr std::size_t kMetaBytes = 3 * 8 + 8 + 3 * 4 + 4 + 16 * 8 + 3 * 8;

/// Encodes `meta` (kMetaBytes bytes).
Bytes encode_meta(const Meta& meta);
/// Decodes and checks a "meta" payload: the exact size, a finite origin within 1e6 m, a finite cell in
/// (0, 1e3] m, 1..65536 cells per axis, the tile size of this build, a finite transform. Throws tridex::Error
/// "<where>: ..." naming the bad field.
Meta decode_meta(const unsigned char* data, std::size_t n, const std::string& where);

/// Rays of a ray set on `lattice` along axis `axis` (nodes of the two other axes).
std::uint64_t ray_count(const Lattice& lattice, int axis);
/// Bytes of an encoded ray set with `rays` rays and `intervals` intervals: 4 per ray + 10 per interval.
std::uint64_t rays_bytes(std::uint64_t rays, std::uint64_t intervals);

/// Encodes one ray set column by column (rays.size() u32 counts, then all enter depths, all exit depths, as f32
/// split into 4 byte planes so that a compressor sees their similar high bytes together, then all enter and
/// all exit materials), in ray order (index u + nu * v). Bit-exact: floats are copied, not converted.
Bytes encode_rays(const RaySet& set);
/// Decodes an encoded ray set into `set` (axis, nu and nv set, rays sized) whose lattice has `cells` cells
/// along the set's axis. Checks: the exact size for `intervals`, counts that sum to `intervals`, and per
/// interval finite depths with 0 <= enter < exit <= cells and each enter above the previous exit. Throws
/// tridex::Error "<where>: ray (u, v) interval i: ..." on the first violation.
void decode_rays(const unsigned char* data, std::size_t n, std::uint64_t intervals, int cells, RaySet& set,
                 const std::string& where);

/// Encodes the tile grid: tiles (3 i32) and one dirty byte per tile (0 clean, 1 dirty: partial flags are
/// written as 1, since the cell boxes are not stored).
Bytes encode_tiles(const TileGrid& tiles);
/// Decodes the tile grid into `tiles`, which must already have the lattice's tile counts (TriDexel::empty);
/// refuses other counts or dirty bytes other than 0 and 1. Throws tridex::Error "<where>: ...".
void decode_tiles(const unsigned char* data, std::size_t n, TileGrid& tiles, const std::string& where);

}  // namespace tridex::compute::tdx
