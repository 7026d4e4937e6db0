// compute/model/tdx_file.cpp - .tdx framing: header, checksummed zstd sections, atomic save, validating load.
#include "compute/model/tdx_file.hpp"

#include <zstd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "compute/model/tdx_codec.hpp"
#include "compute/model/tdx_palette.hpp"
#include "core/atomic_file.hpp"
#include "core/crc32.hpp"
#include "core/error.hpp"

namespace tridex::compute {

namespace {

using tdx::Bytes;

constexpr std::size_t kHeaderBytes = 40;
constexpr std::size_t kSectionHeaderBytes = 32;
constexpr std::uint32_t kSectionCountV1 = 6;  // version 1; version 2 adds the palette
constexpr std::uint32_t kSectionCount = 7;
constexpr std::array<const char*, kSectionCount> kSectionNames = {"meta",   "settings", "rays.x", "rays.y",
                                                                  "rays.z", "tiles",    "palette"};
constexpr std::uint64_t kMaxSettingsBytes = 16u << 20;  // 16 MiB of JSON is far beyond any session's settings

void put32(unsigned char* p, std::uint32_t v) { std::memcpy(p, &v, 4); }
void put64(unsigned char* p, std::uint64_t v) { std::memcpy(p, &v, 8); }
std::uint32_t get32(const unsigned char* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}
std::uint64_t get64(const unsigned char* p) {
    std::uint64_t v;
    std::memcpy(&v, p, 8);
    return v;
}

std::string section_label(std::uint32_t index) {
    return "section " + std::to_string(index + 1) + " ('" + kSectionNames[index] + "')";
}

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};

// Reads exactly n bytes at the current position; the caller has checked them against the file size.
void read_exact(std::FILE* f, unsigned char* out, std::size_t n, const std::string& path) {
    if (n > 0 && std::fread(out, 1, n, f) != n) throw Error(path + ": cannot read (" + std::strerror(errno) + ")");
}

}  // namespace

void save_tdx(const std::string& path, const TriDexel& model, const Mat4& to_world, const std::string& settings_json,
              int level, const MaterialPalette& palette) {
    tdx::Meta meta{model.lattice, to_world, {}};
    for (int a = 0; a < 3; ++a) {
        const RaySet& s = model.sets[a];
        if (s.rays.size() != tdx::ray_count(model.lattice, a))
            throw Error(path + ": ray set " + "xyz"[a] + " does not match the lattice (not saved)");
        for (const auto& ray : s.rays) {
            if (ray.size() > 0xFFFFFFFFu) throw Error(path + ": a ray holds more than 2^32 - 1 intervals (not saved)");
            meta.intervals[a] += ray.size();
        }
    }
    std::array<Bytes, kSectionCount> payloads;
    payloads[0] = tdx::encode_meta(meta);
    payloads[1].assign(settings_json.begin(), settings_json.end());
    for (int a = 0; a < 3; ++a) payloads[2 + a] = tdx::encode_rays(model.sets[a]);
    payloads[5] = tdx::encode_tiles(model.tiles);
    const std::uint32_t sections = palette == default_material_palette() ? kSectionCountV1 : kSectionCount;
    if (sections == kSectionCount) {
        if (const std::string why = palette_problem(palette); !why.empty()) throw Error(path + ": palette: " + why + " (not saved)");
        payloads[6] = tdx::encode_palette(palette);
    }

    std::array<Bytes, kSectionCount> packed;
    std::uint64_t total = kHeaderBytes;
    for (std::uint32_t i = 0; i < sections; ++i) {
        const Bytes& in = payloads[i];
        packed[i].resize(ZSTD_compressBound(in.size()));
        const std::size_t n = ZSTD_compress(packed[i].data(), packed[i].size(), in.data(), in.size(), level);
        if (ZSTD_isError(n)) throw Error(path + ": zstd cannot compress " + section_label(i) + ": " + ZSTD_getErrorName(n));
        packed[i].resize(n);
        total += kSectionHeaderBytes + n;
    }

    unsigned char header[kHeaderBytes] = {};
    std::memcpy(header, kTdxMagic, 8);
    put32(header + 8, sections == kSectionCount ? 2u : 1u);
    put32(header + 12, 0);  // flags
    put32(header + 16, sections);
    put64(header + 24, total);
    put32(header + 32, crc32_ieee(header, 32));
    AtomicFile file(path);
    file.write(header, sizeof header);
    for (std::uint32_t i = 0; i < sections; ++i) {
        unsigned char sh[kSectionHeaderBytes] = {};
        put32(sh, i + 1);
        put32(sh + 4, crc32_ieee(payloads[i].data(), payloads[i].size()));
        put64(sh + 8, payloads[i].size());
        put64(sh + 16, packed[i].size());
        put32(sh + 24, crc32_ieee(packed[i].data(), packed[i].size()));
        put32(sh + 28, crc32_ieee(sh, 28));
        file.write(sh, sizeof sh);
        file.write(packed[i].data(), packed[i].size());
    }
    file.commit();
}

namespace {

// load_tdx; palette_only: the header and the palette alone are checked and read (the other sections skipped, the
// model left empty).
TdxModel read_tdx(const std::string& path, std::size_t max_bytes, const ProgressFn& progress, bool palette_only) {
    std::unique_ptr<std::FILE, FileCloser> f(std::fopen(path.c_str(), "rb"));
    if (!f) throw Error(path + ": cannot open (" + std::strerror(errno) + ")");
    if (std::fseek(f.get(), 0, SEEK_END) != 0) throw Error(path + ": cannot read (not a regular file)");
    const long end = std::ftell(f.get());
    if (end < 0) throw Error(path + ": cannot read (not a regular file)");
    const auto size = static_cast<std::uint64_t>(end);
    std::rewind(f.get());

    unsigned char header[kHeaderBytes] = {};
    read_exact(f.get(), header, static_cast<std::size_t>(std::min<std::uint64_t>(size, kHeaderBytes)), path);
    if (size < 8 || std::memcmp(header, kTdxMagic, 8) != 0)
        throw Error(path + ": not a tridex model file (bad magic; expected \"TDXMODEL\")");
    if (size < kHeaderBytes)
        throw Error(path + ": truncated: " + std::to_string(size) + " bytes, the header alone needs " +
                    std::to_string(kHeaderBytes));
    const std::uint32_t version = get32(header + 8);
    if (version > kTdxVersion)
        throw Error(path + ": format version " + std::to_string(version) + " is newer than this build reads (" +
                    std::to_string(kTdxVersion) + "); use a newer tridex");
    if (version == 0) throw Error(path + ": format version 0 is invalid");
    if (get32(header + 32) != crc32_ieee(header, 32)) throw Error(path + ": checksum mismatch in the file header");
    if (get32(header + 12) != 0)
        throw Error(path + ": unknown flags 0x" + std::to_string(get32(header + 12)) + " (made by a newer tridex?)");
    const std::uint32_t sections = version == 1 ? kSectionCountV1 : kSectionCount;
    if (get32(header + 16) != sections || get32(header + 20) != 0 || get32(header + 36) != 0)
        throw Error(path + ": header has " + std::to_string(get32(header + 16)) + " sections, expected " +
                    std::to_string(sections));
    const std::uint64_t claimed = get64(header + 24);
    if (claimed != size)
        throw Error(path + (claimed > size ? ": truncated: the header says " : ": the header says ") +
                    std::to_string(claimed) + " bytes, the file has " + std::to_string(size));

    TdxModel out;
    if (palette_only && sections == kSectionCountV1) return out;  // version 1: the default palette
    tdx::Meta meta;
    std::uint64_t offset = kHeaderBytes;
    Bytes packed, raw;
    for (std::uint32_t i = 0; i < sections; ++i) {
        const std::string label = section_label(i);
        if (size - offset < kSectionHeaderBytes)
            throw Error(path + ": truncated: " + label + " header at offset " + std::to_string(offset) + ", the file has " +
                        std::to_string(size) + " bytes");
        unsigned char sh[kSectionHeaderBytes];
        read_exact(f.get(), sh, sizeof sh, path);
        offset += kSectionHeaderBytes;
        if (get32(sh + 28) != crc32_ieee(sh, 28)) throw Error(path + ": checksum mismatch in the header of " + label);
        if (get32(sh) != i + 1)
            throw Error(path + ": " + label + " has id " + std::to_string(get32(sh)) + ", expected " + std::to_string(i + 1));
        const std::uint32_t crc = get32(sh + 4);
        const std::uint64_t raw_n = get64(sh + 8), packed_n = get64(sh + 16);
        if (packed_n > size - offset)
            throw Error(path + ": truncated: " + label + " needs " + std::to_string(packed_n) + " bytes at offset " +
                        std::to_string(offset) + ", the file has " + std::to_string(size));
        if (palette_only && i + 1 < sections) {  // not the palette: skipped
            if (std::fseek(f.get(), static_cast<long>(packed_n), SEEK_CUR) != 0) throw Error(path + ": cannot read");
            offset += packed_n;
            continue;
        }
        // What the section must hold, known before anything is allocated for it.
        std::uint64_t expect = 0;
        if (i == 0) expect = tdx::kMetaBytes;
        else if (i == 1) expect = raw_n <= kMaxSettingsBytes ? raw_n : kMaxSettingsBytes + 1;
        else if (i <= 4) expect = tdx::rays_bytes(out.model.sets[i - 2].rays.size(), meta.intervals[i - 2]);
        else if (i == 5) expect = 12 + out.model.tiles.dirty.size();
        else expect = raw_n <= tdx::kPaletteBytesMax ? raw_n : tdx::kPaletteBytesMax + 1;
        if (raw_n != expect)
            throw Error(path + ": " + label + " claims " + std::to_string(raw_n) + " bytes, " +
                        (i == 1   ? std::string("more than settings may take")
                         : i == 6 ? std::string("more than a palette may take")
                                  : "the model needs " + std::to_string(expect)));
        packed.resize(packed_n);
        read_exact(f.get(), packed.data(), packed.size(), path);
        offset += packed_n;
        if (crc32_ieee(packed.data(), packed.size()) != get32(sh + 24))
            throw Error(path + ": checksum mismatch in section '" + kSectionNames[i] + "' (compressed data)");
        const unsigned long long frame = ZSTD_getFrameContentSize(packed.data(), packed.size());
        if (frame != raw_n)
            throw Error(path + ": " + label + ": the compressed data is corrupt (its frame does not hold " +
                        std::to_string(raw_n) + " bytes)");
        raw.resize(raw_n);
        const std::size_t got = ZSTD_decompress(raw.data(), raw.size(), packed.data(), packed.size());
        if (ZSTD_isError(got) || got != raw_n)
            throw Error(path + ": " + label + ": the compressed data is corrupt" +
                        (ZSTD_isError(got) ? std::string(" (zstd: ") + ZSTD_getErrorName(got) + ")" : std::string()));
        if (crc32_ieee(raw.data(), raw.size()) != crc)
            throw Error(path + ": checksum mismatch in section '" + kSectionNames[i] + "'");
        const std::string where = path + ": section '" + std::string(kSectionNames[i]) + "'";
        if (i == 0) {
            meta = tdx::decode_meta(raw.data(), raw.size(), where);
            std::uint64_t rays = 0, intervals = 0;
            for (int a = 0; a < 3; ++a) {
                rays += tdx::ray_count(meta.lattice, a);
                if (meta.intervals[a] > (std::uint64_t{1} << 40))
                    throw Error(where + ": " + std::to_string(meta.intervals[a]) + " intervals in one set is impossible");
                intervals += meta.intervals[a];
            }
            const std::uint64_t need = rays * sizeof(std::vector<Interval>) + intervals * sizeof(Interval);
            if (need > max_bytes)
                throw Error(where + ": the model needs " + std::to_string(need >> 20) + " MiB, more than the " +
                            std::to_string(max_bytes >> 20) + " MiB available");
            out.model = TriDexel::empty(meta.lattice, max_bytes);
            out.to_world = meta.to_world;
        } else if (i == 1) {
            out.settings_json.assign(raw.begin(), raw.end());
        } else if (i <= 4) {
            const int a = static_cast<int>(i) - 2;
            tdx::decode_rays(raw.data(), raw.size(), meta.intervals[a], meta.lattice.cells[a], out.model.sets[a], where);
        } else if (i == 5) {
            tdx::decode_tiles(raw.data(), raw.size(), out.model.tiles, where);
        } else {
            out.palette = tdx::decode_palette(raw.data(), raw.size(), where);
        }
        report_progress(progress, static_cast<double>(offset), static_cast<double>(size));
    }
    if (offset != size) throw Error(path + ": " + std::to_string(size - offset) + " bytes after the last section");
    return out;
}

}  // namespace

TdxModel load_tdx(const std::string& path, std::size_t max_bytes, const ProgressFn& progress) {
    return read_tdx(path, max_bytes, progress, false);
}

MaterialPalette load_tdx_palette(const std::string& path) { return read_tdx(path, 0, {}, true).palette; }

}  // namespace tridex::compute
