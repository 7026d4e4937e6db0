// compute/gpu/gpu_contourer_pool.cpp - the GPU contourer's per-tile regions (allocation, compaction, growth),
// host contouring of tiles beyond the kernel's lists from rays read out of the slabs, read-back for tests.
#include "compute/gpu/gpu_contourer.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

#include "compute/contour/contour_qef.hpp"
#include "core/error.hpp"

namespace tridex::compute {
namespace {

constexpr std::size_t kVertexD = 24;  // bytes of one vertex's double position (3 x f64)

std::uint32_t slack(std::uint32_t n, std::uint32_t extra) { return n + n / 2 + extra; }

}  // namespace

void GpuContourer::write_command(std::uint32_t tile) {
    const Region& r = regions_[tile];
    const std::uint32_t c[5] = {r.iused, 1u, r.ioff, r.voff, 0u};
    commands_.write(c, sizeof(c), static_cast<std::size_t>(tile) * 20);
    const std::uint32_t g[4] = {r.voff, r.vcap, r.ioff, r.icap};
    regions_buf_.write(g, sizeof(g), static_cast<std::size_t>(tile) * 16);
}

void GpuContourer::reserve(std::uint32_t tile, std::uint32_t nv, std::uint32_t ni) {
    Region& r = regions_[tile];
    if (r.vcap >= nv && r.icap >= ni) return;
    // The tile's old region is abandoned (it is about to be rewritten); compaction reclaims it.
    r = Region{};
    write_command(tile);
    const std::uint32_t vcap = slack(nv, 32), icap = slack(ni, 96);
    if (vhead_ + vcap > vpool_ || ihead_ + icap > ipool_) regrow(vcap, icap);
    r.voff = static_cast<std::uint32_t>(vhead_);
    r.vcap = vcap;
    r.ioff = static_cast<std::uint32_t>(ihead_);
    r.icap = icap;
    vhead_ += vcap;
    ihead_ += icap;
    write_command(tile);
}

void GpuContourer::regrow(std::size_t extra_v, std::size_t extra_i) {
    std::size_t live_v = 0, live_i = 0;
    for (const Region& r : regions_) {
        live_v += r.vcap;
        live_i += r.icap;
    }
    const std::size_t nv = std::max(vpool_, 2 * (live_v + extra_v)), ni = std::max(ipool_, 2 * (live_i + extra_i));
    const std::size_t range = context_.properties().limits.maxStorageBufferRange;
    if (nv * kVertexD > range || ni * 4 > range || nv > std::numeric_limits<std::int32_t>::max())
        throw Error("GPU contouring: the surface needs " + std::to_string(live_v + extra_v) + " vertices and " +
                    std::to_string(live_i + extra_i) + " indices, more than one " + std::to_string(range / (1024 * 1024)) +
                    " MiB buffer binding holds; lower --resolution or contour on the CPU");
    gpu::Buffer v = gpu::Buffer::create(context_, nv * sizeof(GpuContourVertex), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, gpu::MemoryDomain::kHost);
    gpu::Buffer vd = gpu::Buffer::create(context_, nv * kVertexD, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryDomain::kHost);
    gpu::Buffer ix = gpu::Buffer::create(context_, ni * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT, gpu::MemoryDomain::kHost);
    std::size_t vh = 0, ih = 0;
    for (std::uint32_t t = 0; t < regions_.size(); ++t) {
        Region& r = regions_[t];
        if (r.vcap == 0 && r.icap == 0) continue;
        auto* src_v = static_cast<const char*>(vertices_.mapped());
        auto* src_d = static_cast<const char*>(vertices_d_.mapped());
        auto* src_i = static_cast<const char*>(indices_.mapped());
        std::memcpy(static_cast<char*>(v.mapped()) + vh * sizeof(GpuContourVertex), src_v + std::size_t{r.voff} * sizeof(GpuContourVertex), std::size_t{r.vused} * sizeof(GpuContourVertex));
        std::memcpy(static_cast<char*>(vd.mapped()) + vh * kVertexD, src_d + std::size_t{r.voff} * kVertexD, std::size_t{r.vused} * kVertexD);
        std::memcpy(static_cast<char*>(ix.mapped()) + ih * 4, src_i + std::size_t{r.ioff} * 4, std::size_t{r.iused} * 4);
        r.voff = static_cast<std::uint32_t>(vh);
        r.ioff = static_cast<std::uint32_t>(ih);
        vh += r.vcap;
        ih += r.icap;
        write_command(t);
    }
    vertices_ = std::move(v);
    vertices_d_ = std::move(vd);
    indices_ = std::move(ix);
    vpool_ = nv;
    ipool_ = ni;
    vhead_ = vh;
    ihead_ = ih;
    ++generation_;
    ++stats_.pool_grows;
}

void GpuContourer::fill_scratch_rays(std::uint32_t tile) {
    if (!scratch_) scratch_ = std::make_unique<TriDexel>(TriDexel::empty(lattice_, std::numeric_limits<std::size_t>::max()));
    constexpr int kT = TileGrid::kTileCells;
    const int t[3] = {static_cast<int>(tile % static_cast<std::uint32_t>(tiles_[0])),
                      static_cast<int>(tile / static_cast<std::uint32_t>(tiles_[0]) % static_cast<std::uint32_t>(tiles_[1])),
                      static_cast<int>(tile / static_cast<std::uint32_t>(tiles_[0] * tiles_[1]))};
    // TileContourer::run reads rays through nodes t*16 - 5 .. t*16 + 21 of each axis: crossings on edges from
    // nodes t*16 - 2 .. t*16 + 17 (the cached cells' edges and, for the corner fill, those of their face-adjacent
    // cells), occupancy X rays from t*16 - 2 up to t*16 + 18, the normals' neighbour rays one node beside the
    // crossings, and the lines between a crossing's ray and its neighbour that the one-sided slope's gap check
    // reads (contour_qef.cpp same_surface) at up to kNormalWindow + 1 nodes from the crossing's edge node along
    // the ray axis (t*16 - 5 .. t*16 + 20); the copy takes one more node, to t*16 + 21.
    constexpr int kReach = 5;
    static_assert(kReach >= 2 + static_cast<int>(contour::kNormalWindow) + 1, "the copy must reach the gap check's lines");
    for (int a = 0; a < 3; ++a) {
        const int ua = (a + 1) % 3, va = (a + 2) % 3;
        RaySet& set = scratch_->sets[a];
        for (int v = std::max(0, t[va] * kT - kReach); v <= std::min(lattice_.cells[va], t[va] * kT + kT + kReach); ++v)
            for (int u = std::max(0, t[ua] * kT - kReach); u <= std::min(lattice_.cells[ua], t[ua] * kT + kT + kReach); ++u)
                slabs_.read_ray(a, u, v, set.ray(u, v));
    }
}

const contour::TileMesh& GpuContourer::host_piece(std::uint32_t tile) {
    const auto it = pieces_.find(tile);
    if (it != pieces_.end()) return it->second;
    fill_scratch_rays(tile);
    contour::TileMesh& piece = pieces_[tile];
    const std::array<int, 3> t{static_cast<int>(tile % static_cast<std::uint32_t>(tiles_[0])),
                               static_cast<int>(tile / static_cast<std::uint32_t>(tiles_[0]) % static_cast<std::uint32_t>(tiles_[1])),
                               static_cast<int>(tile / static_cast<std::uint32_t>(tiles_[0] * tiles_[1]))};
    worker_.run(*scratch_, t, piece);
    return piece;
}

void GpuContourer::contour_on_host(std::uint32_t tile) {
    const contour::TileMesh& piece = host_piece(tile);
    contour::KeyCodec codec;
    for (int a = 0; a < 3; ++a) {
        codec.nodes[a] = lattice_.cells[a] + 1;
        codec.tiles[a] = tiles_[a];
    }
    // Own vertices, then copies of the borrowed ones (found in their owner tiles' host pieces).
    std::vector<Vec3> pos(piece.grid);
    std::vector<std::uint8_t> mat(piece.materials);
    for (const contour::VertexKey key : piece.foreign) {
        const contour::TileMesh& owner = host_piece(static_cast<std::uint32_t>(codec.owner_tile(key)));
        const auto it = std::lower_bound(owner.keys.begin(), owner.keys.end(), key);
        if (it == owner.keys.end() || *it != key)
            throw Error("GPU contouring: tile " + std::to_string(tile) + " borrows a vertex its neighbour lacks (internal error)");
        pos.push_back(owner.grid[static_cast<std::size_t>(it - owner.keys.begin())]);
        mat.push_back(owner.materials[static_cast<std::size_t>(it - owner.keys.begin())]);
    }
    std::vector<std::uint32_t> ix;
    ix.reserve(piece.triangles.size() * 3);
    const auto own = static_cast<std::uint32_t>(piece.keys.size());
    for (const auto& tri : piece.triangles)
        for (const std::uint32_t r : tri) ix.push_back(r < contour::TileMesh::kForeign ? r : own + (r - contour::TileMesh::kForeign));
    reserve(tile, static_cast<std::uint32_t>(pos.size()), static_cast<std::uint32_t>(ix.size()));
    Region& r = regions_[tile];
    auto* v = static_cast<GpuContourVertex*>(vertices_.mapped()) + r.voff;
    auto* d = static_cast<double*>(vertices_d_.mapped()) + std::size_t{r.voff} * 3;
    for (std::size_t i = 0; i < pos.size(); ++i) {
        v[i] = GpuContourVertex{{static_cast<float>(pos[i].x), static_cast<float>(pos[i].y), static_cast<float>(pos[i].z)}, mat[i]};
        d[3 * i] = pos[i].x;
        d[3 * i + 1] = pos[i].y;
        d[3 * i + 2] = pos[i].z;
    }
    if (!ix.empty()) indices_.write(ix.data(), ix.size() * 4, std::size_t{r.ioff} * 4);
    r.vused = static_cast<std::uint32_t>(pos.size());
    r.iused = static_cast<std::uint32_t>(ix.size());
    write_command(tile);
}

void GpuContourer::download_tile(std::size_t tile, std::vector<GpuContourVertex>& vertices,
                                 std::vector<std::array<std::uint32_t, 3>>& triangles, std::vector<Vec3>* grid) const {
    tile_index_count(tile);  // range check
    const Region& r = regions_[tile];
    const auto* v = static_cast<const GpuContourVertex*>(vertices_.mapped()) + r.voff;
    vertices.assign(v, v + r.vused);
    if (grid) {
        const auto* d = static_cast<const double*>(vertices_d_.mapped()) + std::size_t{r.voff} * 3;
        grid->resize(r.vused);
        for (std::size_t i = 0; i < r.vused; ++i) (*grid)[i] = Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2]);
    }
    const auto* ix = static_cast<const std::uint32_t*>(indices_.mapped()) + r.ioff;
    triangles.resize(r.iused / 3);
    for (std::size_t i = 0; i < triangles.size(); ++i) {
        triangles[i] = {ix[3 * i], ix[3 * i + 1], ix[3 * i + 2]};
        for (const std::uint32_t k : triangles[i])
            if (k >= r.vused) throw Error("GPU contouring: tile " + std::to_string(tile) + " has an index beyond its vertices");
    }
}

TriMesh GpuContourer::download(std::vector<std::uint8_t>* materials) const {
    TriMesh m;
    if (materials) materials->clear();
    std::vector<GpuContourVertex> verts;
    std::vector<std::array<std::uint32_t, 3>> tris;
    for (std::size_t t = 0; t < regions_.size(); ++t) {
        const Region& r = regions_[t];
        if (r.iused == 0) continue;
        download_tile(t, verts, tris);
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        const auto* d = static_cast<const double*>(vertices_d_.mapped()) + std::size_t{r.voff} * 3;
        for (std::size_t i = 0; i < verts.size(); ++i) {
            m.positions.push_back(lattice_.to_world(Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2])));
            if (materials) materials->push_back(static_cast<std::uint8_t>(verts[i].material));
        }
        for (const auto& tri : tris) m.triangles.push_back({base + tri[0], base + tri[1], base + tri[2]});
    }
    return m;
}

}  // namespace tridex::compute
