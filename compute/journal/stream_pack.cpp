// compute/journal/stream_pack.cpp - zstd frames of a stream's bytes (zstd's simple API; zstd.h, "Simple API").
#include "compute/journal/stream_pack.hpp"

#include <zstd.h>

#include "core/error.hpp"

namespace tridex::compute {

std::vector<unsigned char> pack_bytes(std::span<const unsigned char> bytes, int level) {
    std::vector<unsigned char> out(ZSTD_compressBound(bytes.size()));
    const std::size_t n = ZSTD_compress(out.data(), out.size(), bytes.data(), bytes.size(), level);
    if (ZSTD_isError(n)) throw Error(std::string("zstd: ") + ZSTD_getErrorName(n));
    out.resize(n);
    return out;
}

std::vector<unsigned char> unpack_bytes(std::span<const unsigned char> frame, std::size_t max_bytes, const std::string& what) {
    const unsigned long long size = ZSTD_getFrameContentSize(frame.data(), frame.size());
    if (size == ZSTD_CONTENTSIZE_ERROR) throw Error(what + ": not a zstd frame");
    if (size == ZSTD_CONTENTSIZE_UNKNOWN) throw Error(what + ": the zstd frame does not say its size");
    if (size > max_bytes)
        throw Error(what + ": the zstd frame holds " + std::to_string(size) + " bytes, over the limit of " +
                    std::to_string(max_bytes));
    std::vector<unsigned char> out(static_cast<std::size_t>(size));
    const std::size_t n = ZSTD_decompress(out.data(), out.size(), frame.data(), frame.size());
    if (ZSTD_isError(n)) throw Error(what + ": zstd: " + ZSTD_getErrorName(n));
    if (n != out.size()) throw Error(what + ": the zstd frame unpacked to " + std::to_string(n) + " bytes, not " + std::to_string(out.size()));
    return out;
}

}  // namespace tridex::compute
