// compute/model/tdx_codec.cpp - section payloads of the .tdx model file, encoded and checked.
#include "compute/model/tdx_codec.hpp"

#include <bit>
#include <cmath>
#include <cstring>

#include "core/error.hpp"
#include "core/tool_sample.hpp"

namespace tridex::compute::tdx {

static_assert(std::endian::native == std::endian::little, "the .tdx codec copies little-endian values as they are");

namespace {

class Writer {
public:
    explicit Writer(Bytes& out) : out_(out) {}
    template <class T>
    void put(const T& v) {
        const auto* p = reinterpret_cast<const unsigned char*>(&v);
        out_.insert(out_.end(), p, p + sizeof(T));
    }

private:
    Bytes& out_;
};

class Reader {
public:
    explicit Reader(const unsigned char* p) : p_(p) {}
    template <class T>
    T get() {
        T v;
        std::memcpy(&v, p_ + at_, sizeof(T));  // callers check the total size first
        at_ += sizeof(T);
        return v;
    }

private:
    const unsigned char* p_;
    std::size_t at_ = 0;
};

std::string num(double v) { return std::to_string(v); }

}  // namespace

Bytes encode_meta(const Meta& m) {
    Bytes out;
    out.reserve(kMetaBytes);
    Writer w(out);
    for (int a = 0; a < 3; ++a) w.put<double>(m.lattice.origin_m[a]);
    w.put<double>(m.lattice.cell_m);
    for (int a = 0; a < 3; ++a) w.put<std::int32_t>(m.lattice.cells[a]);
    w.put<std::int32_t>(TileGrid::kTileCells);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) w.put<double>(m.to_world[c][r]);
    for (int a = 0; a < 3; ++a) w.put<std::uint64_t>(m.intervals[a]);
    return out;
}

Meta decode_meta(const unsigned char* data, std::size_t n, const std::string& where) {
    if (n != kMetaBytes)
        throw Error(where + ": " + std::to_string(n) + " bytes, expected " + std::to_string(kMetaBytes));
    Reader r(data);
    Meta m;
    for (int a = 0; a < 3; ++a) {
        m.lattice.origin_m[a] = r.get<double>();
        if (!(std::abs(m.lattice.origin_m[a]) <= 1e6))
            throw Error(where + ": lattice origin " + num(m.lattice.origin_m[a]) + " m is not finite or beyond 1e6 m");
    }
    m.lattice.cell_m = r.get<double>();
    if (!(m.lattice.cell_m > 0.0 && m.lattice.cell_m <= 1e3))
        throw Error(where + ": cell size " + num(m.lattice.cell_m) + " m is not in (0, 1000] m");
    for (int a = 0; a < 3; ++a) {
        m.lattice.cells[a] = r.get<std::int32_t>();
        if (m.lattice.cells[a] < 1 || m.lattice.cells[a] > 65536)
            throw Error(where + ": " + std::to_string(m.lattice.cells[a]) + " cells along " + "xyz"[a] +
                        " (must be 1..65536)");
    }
    const std::int32_t tile = r.get<std::int32_t>();
    if (tile != TileGrid::kTileCells)
        throw Error(where + ": tiles of " + std::to_string(tile) + " cells; this build uses " +
                    std::to_string(TileGrid::kTileCells));
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row) {
            m.to_world[c][row] = r.get<double>();
            if (!std::isfinite(m.to_world[c][row])) throw Error(where + ": the workpiece transform is not finite");
        }
    for (int a = 0; a < 3; ++a) m.intervals[a] = r.get<std::uint64_t>();
    return m;
}

std::uint64_t ray_count(const Lattice& lattice, int axis) {
    return static_cast<std::uint64_t>(lattice.nodes((axis + 1) % 3)) * static_cast<std::uint64_t>(lattice.nodes((axis + 2) % 3));
}

std::uint64_t rays_bytes(std::uint64_t rays, std::uint64_t intervals) { return 4 * rays + 10 * intervals; }

Bytes encode_rays(const RaySet& set) {
    std::uint64_t n = 0;
    for (const auto& ray : set.rays) n += ray.size();
    Bytes out(rays_bytes(set.rays.size(), n));
    unsigned char* counts = out.data();
    unsigned char* enter = counts + 4 * set.rays.size();  // 4 planes of n bytes each
    unsigned char* exit = enter + 4 * n;
    unsigned char* enter_mat = exit + 4 * n;
    unsigned char* exit_mat = enter_mat + n;
    std::size_t i = 0;
    for (std::size_t r = 0; r < set.rays.size(); ++r) {
        const auto c = static_cast<std::uint32_t>(set.rays[r].size());
        std::memcpy(counts + 4 * r, &c, 4);
        for (const Interval& iv : set.rays[r]) {
            const auto e = std::bit_cast<std::uint32_t>(iv.enter), x = std::bit_cast<std::uint32_t>(iv.exit);
            for (int b = 0; b < 4; ++b) {
                enter[b * n + i] = static_cast<unsigned char>(e >> (8 * b));
                exit[b * n + i] = static_cast<unsigned char>(x >> (8 * b));
            }
            enter_mat[i] = iv.enter_material;
            exit_mat[i] = iv.exit_material;
            ++i;
        }
    }
    return out;
}

void decode_rays(const unsigned char* data, std::size_t size, std::uint64_t n, int cells, RaySet& set,
                 const std::string& where) {
    const std::uint64_t rays = set.rays.size();
    if (size != rays_bytes(rays, n))
        throw Error(where + ": " + std::to_string(size) + " bytes, expected " + std::to_string(rays_bytes(rays, n)) +
                    " for " + std::to_string(rays) + " rays and " + std::to_string(n) + " intervals");
    const unsigned char* counts = data;
    const unsigned char* enter = counts + 4 * rays;
    const unsigned char* exit = enter + 4 * n;
    const unsigned char* enter_mat = exit + 4 * n;
    const unsigned char* exit_mat = enter_mat + n;
    std::uint64_t total = 0;
    for (std::uint64_t r = 0; r < rays; ++r) {
        std::uint32_t c;
        std::memcpy(&c, counts + 4 * r, 4);
        total += c;
        if (total > n)
            throw Error(where + ": ray counts add up to more than the " + std::to_string(n) + " intervals of the set");
    }
    if (total != n)
        throw Error(where + ": ray counts add up to " + std::to_string(total) + ", not " + std::to_string(n));
    const float top = static_cast<float>(cells);
    std::uint64_t i = 0;
    for (std::uint64_t r = 0; r < rays; ++r) {
        std::uint32_t c;
        std::memcpy(&c, counts + 4 * r, 4);
        auto& ray = set.rays[r];
        ray.resize(c);
        float prev_exit = -1.0f;
        for (std::uint32_t k = 0; k < c; ++k, ++i) {
            std::uint32_t e = 0, x = 0;
            for (int b = 0; b < 4; ++b) {
                e |= static_cast<std::uint32_t>(enter[b * n + i]) << (8 * b);
                x |= static_cast<std::uint32_t>(exit[b * n + i]) << (8 * b);
            }
            Interval& iv = ray[k];
            iv.enter = std::bit_cast<float>(e);
            iv.exit = std::bit_cast<float>(x);
            iv.enter_material = enter_mat[i];
            iv.exit_material = exit_mat[i];
            // !(a <= b) is true for NaN too: non-finite depths fail these comparisons.
            if (!(iv.enter >= 0.0f && iv.enter < iv.exit && iv.exit <= top && iv.enter > prev_exit)) {
                const std::uint64_t u = r % static_cast<std::uint64_t>(set.nu), v = r / static_cast<std::uint64_t>(set.nu);
                throw Error(where + ": ray (" + std::to_string(u) + ", " + std::to_string(v) + ") interval " +
                            std::to_string(k) + ": depths [" + std::to_string(iv.enter) + ", " + std::to_string(iv.exit) +
                            "] are not finite, ordered, after the previous interval and within 0.." + std::to_string(cells));
            }
            if (iv.enter_material > kMaxMaterialId || iv.exit_material > kMaxMaterialId) {
                const std::uint64_t u = r % static_cast<std::uint64_t>(set.nu), v = r / static_cast<std::uint64_t>(set.nu);
                throw Error(where + ": ray (" + std::to_string(u) + ", " + std::to_string(v) + ") interval " +
                            std::to_string(k) + ": material ids " + std::to_string(iv.enter_material) + ", " +
                            std::to_string(iv.exit_material) + " are not both material ids (0.." +
                            std::to_string(kMaxMaterialId) + ")");
            }
            prev_exit = iv.exit;
        }
    }
}

Bytes encode_tiles(const TileGrid& tiles) {
    Bytes out;
    Writer w(out);
    for (int a = 0; a < 3; ++a) w.put<std::int32_t>(tiles.tiles[a]);
    // A partial flag is written as whole: the cell boxes are not stored, and whole is always safe.
    for (const std::uint8_t d : tiles.dirty) out.push_back(d != 0 ? TileGrid::kWhole : std::uint8_t{0});
    return out;
}

void decode_tiles(const unsigned char* data, std::size_t n, TileGrid& tiles, const std::string& where) {
    if (n != 12 + tiles.dirty.size())
        throw Error(where + ": " + std::to_string(n) + " bytes, expected " + std::to_string(12 + tiles.dirty.size()));
    Reader r(data);
    for (int a = 0; a < 3; ++a)
        if (r.get<std::int32_t>() != tiles.tiles[a])
            throw Error(where + ": tile counts do not match the lattice");
    for (std::size_t t = 0; t < tiles.dirty.size(); ++t) {
        const unsigned char d = data[12 + t];
        if (d > 1) throw Error(where + ": tile " + std::to_string(t) + " has dirty flag " + std::to_string(d));
        tiles.dirty[t] = d;
    }
}

}  // namespace tridex::compute::tdx
