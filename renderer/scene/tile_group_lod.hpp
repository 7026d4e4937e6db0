// renderer/scene/tile_group_lod.hpp - levels of detail over groups of workpiece tiles: which group each eye
// draws in place of its tiles.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/aabb.hpp"
#include "renderer/scene/tile_lod.hpp"

namespace tridex::renderer {

/// A group of neighbouring tiles (e.g. compute::TileGroupSurface) with levels of detail over the whole group,
/// whose outer border is its tiles' full-resolution border: one of its levels may be drawn instead of every
/// tile (and smaller group) under it, without cracks against the neighbours.
struct TileGroup {
    static constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
    std::uint64_t id = 0;       ///< stable identity across frames (distinct from every other group's)
    Aabb bounds_m;              ///< world box holding every tile under the group, m
    std::uint64_t version = 0;  ///< changes whenever its levels change (re-uploaded then)
    std::span<const TileMeshLevel> levels{};  ///< finest first; empty: never drawn (its children are)
    std::size_t parent = kNone;  ///< index of the enclosing group in the same list, or kNone
    /// false: what lies under the group cannot draw all of its surface yet (a coarse-first start-up whose tiles
    /// are not all contoured, compute::TileGroupSurface::children_cover), so the group is drawn at its coarsest level
    /// within the bound, else its finest, unless an enclosing group is drawn.
    bool children_cover = true;
    /// true while its levels are being (re)built (compute::TileGroupSurface::levels_waiting): an enclosing group
    /// with a level is then drawn over the bound rather than descend to this group's children, which would draw the
    /// group's surface at a finer level than it needs, up to its tiles at full resolution.
    bool levels_waiting = false;
    /// The groups of the same depth around this one: slot 9 (dz + 1) + 3 (dy + 1) + (dx + 1) holds the index (in the
    /// same list) of the group at offset (dx, dy, dz), or kNone where there is none (slot 13 is the group itself and
    /// unused). Read only where a level has own triangles and joins (TileMeshLevel).
    std::array<std::size_t, 27> neighbours = no_neighbours();

    /// Every slot of `neighbours` kNone: the default, no neighbour linked (a level with joins is then drawn whole).
    static constexpr std::array<std::size_t, 27> no_neighbours() {
        std::array<std::size_t, 27> a{};
        a.fill(kNone);
        return a;
    }
};

/// Per group, 1 when its children cannot draw it at their own levels yet: what lies under it does not cover it
/// (TileGroup::children_cover false), or one of its child groups' levels are waiting (TileGroup::levels_waiting).
/// Throws tridex::Error when a parent index is out of range.
std::vector<std::uint8_t> groups_standing_in(std::span<const TileGroup> groups);

/// Per group, what an eye draws: 0 = not this group (an enclosing group is drawn, or none of its levels is
/// within the bound and its children are considered), k >= 1 = its level k (1-based into levels).
/// `covered` gets, per group, 1 when an enclosing group is drawn (the group and its tiles are then not drawn).
/// A group is drawn at its coarsest level whose error_m * px_per_m[g] <= max_px, unless an enclosing group is
/// drawn; so every tile is drawn at most once, by itself or by exactly one group. A group with levels that stands in
/// for its children (groups_standing_in: they do not cover it, or a child group's levels are waiting) is drawn
/// whatever its error: its finest level when none is within the bound. px_per_m: per group, the
/// pixels_per_metre of its bounds in the eye (size = groups.size()). Throws tridex::Error when sizes differ or a
/// parent index is out of range or parents form a cycle.
std::vector<std::size_t> choose_group_levels(std::span<const TileGroup> groups, std::span<const double> px_per_m,
                                             double max_px, std::vector<std::uint8_t>& covered);

/// Per group, 1 when an eye draws only the own triangles (TileMeshLevel::own_triangles) of the level it chose for it:
/// that level (`level`, 1-based per group, as choose_group_levels gives; 0 = not drawn) has own triangles, and every
/// neighbour its joins name (TileMeshLevel::joins, TileGroup::neighbours) is `visible` to the eye and drawn at a level
/// with own triangles too, the same depth's coarse contour, whose triangles meet these at the border exactly. A joined
/// neighbour that is missing, hidden or drawn otherwise (an enclosing group, its children, a simplified level) needs
/// the ring and skirt. Throws tridex::Error when sizes differ or a level or neighbour index is out of range.
std::vector<std::uint8_t> groups_drawn_own_only(std::span<const TileGroup> groups, std::span<const std::size_t> level,
                                                std::span<const std::uint8_t> visible);

/// True when `group` drawn at `level` (1-based, as choose_group_levels gives) is within the pixel bound: that level's
/// error_m (m) times px_per_m (pixels per metre at the group's bounds) is at most max_px. False for level 0 (not drawn)
/// or out of range.
bool level_within_bound(const TileGroup& group, std::size_t level, double px_per_m, double max_px);

/// True when an eye draws `group` at `level` (1-based, as choose_group_levels gives) only because it stands in for
/// its children (`stands_in`, from groups_standing_in) while that level's error_m * px_per_m exceeds max_px: the eye
/// wants the group's tiles, or its child groups' levels (compute::DetailRequests). False for level 0 or out of range.
bool wants_detail(const TileGroup& group, std::size_t level, double px_per_m, double max_px, bool stands_in);

}  // namespace tridex::renderer
