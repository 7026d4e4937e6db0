// compute/journal/stream_pack.hpp - a stream's bytes packed with zstd for a slow link (a shared session's backlog):
// one zstd frame holding the content size.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace tridex::compute {

/// `bytes` as one zstd frame at `level` (1..19) with the content size in its header. Throws tridex::Error when zstd
/// fails (out of memory).
std::vector<unsigned char> pack_bytes(std::span<const unsigned char> bytes, int level = 3);

/// The bytes of one zstd frame written by pack_bytes. Throws tridex::Error "<what>: ..." when it is not one frame,
/// does not name its content size, names more than max_bytes, or does not unpack to exactly that size.
std::vector<unsigned char> unpack_bytes(std::span<const unsigned char> frame, std::size_t max_bytes, const std::string& what);

}  // namespace tridex::compute
