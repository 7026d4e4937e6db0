// gpu/indirect_workpiece.hpp - a tiled workpiece surface that lives in GPU buffers (as
// compute/gpu/gpu_contourer.hpp fills them), for the stereo renderer to draw with one indirect draw per tile.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/aabb.hpp"
#include "core/math.hpp"

namespace tridex::renderer {

/// One non-empty tile of an IndirectWorkpiece: its draw command's index (the command sits at
/// id * 20 bytes of IndirectWorkpiece::commands), its index count (> 0) and its world bounds (m, for culling).
struct IndirectTile {
    std::uint32_t id = 0;
    std::uint32_t index_count = 0;
    Aabb bounds_m;
    std::uint64_t version = 0;  ///< content version of the tile's contour (changes whenever it is redone)
};

/// Device buffers of the workpiece surface: `vertices` (16-byte vertices: float grid position[3] in grid
/// units, uint material id), `indices` (uint32, tile-local), `commands` (VkDrawIndexedIndirectCommand
/// records, stride 20 bytes, each with firstIndex / vertexOffset set and instanceCount 1), the grid ->
/// world transform (m) and the tiles to draw. The buffers must stay alive and unwritten while a frame
/// that draws them is recorded and runs (the renderer's draw()/render() are synchronous).
struct IndirectWorkpiece {
    VkBuffer vertices = VK_NULL_HANDLE;
    VkBuffer indices = VK_NULL_HANDLE;
    VkBuffer commands = VK_NULL_HANDLE;
    glm::mat4 world_from_grid{1.0f};  ///< world m = origin + grid * cell
    Vec3 grid_origin_m{0.0};          ///< the lattice origin (world m) that world_from_grid holds in float
    double cell_m = 1.0;              ///< the lattice cell size (m) that world_from_grid holds in float
    std::vector<IndirectTile> tiles;  ///< the non-empty tiles, by id
    std::uint64_t triangles = 0;      ///< sum of index counts / 3 (for reports)
};

}  // namespace tridex::renderer
