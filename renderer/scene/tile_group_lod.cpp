// renderer/scene/tile_group_lod.cpp - top-down choice of group levels per eye.
#include "renderer/scene/tile_group_lod.hpp"

#include <string>

#include "core/error.hpp"

namespace tridex::renderer {

std::vector<std::uint8_t> groups_standing_in(std::span<const TileGroup> groups) {
    std::vector<std::uint8_t> out(groups.size(), 0);
    for (std::size_t g = 0; g < groups.size(); ++g) {
        if (!groups[g].children_cover) out[g] = 1;
        const std::size_t p = groups[g].parent;
        if (p == TileGroup::kNone) continue;
        if (p >= groups.size()) throw Error("groups_standing_in: parent index " + std::to_string(p) + " out of range");
        if (groups[g].levels_waiting) out[p] = 1;
    }
    return out;
}

std::vector<std::size_t> choose_group_levels(std::span<const TileGroup> groups, std::span<const double> px_per_m,
                                             double max_px, std::vector<std::uint8_t>& covered) {
    const std::size_t n = groups.size();
    if (px_per_m.size() != n)
        throw Error("choose_group_levels: " + std::to_string(px_per_m.size()) + " scales for " + std::to_string(n) + " groups");
    const std::vector<std::uint8_t> stands_in = groups_standing_in(groups);
    std::vector<std::size_t> level(n, 0);
    covered.assign(n, 0);
    // 0 = unresolved, 1 = resolving, 2 = resolved.
    std::vector<std::uint8_t> state(n, 0);
    std::vector<std::size_t> chain;
    for (std::size_t start = 0; start < n; ++start) {
        // Walk up to the first resolved group (or a root), then resolve back down: parents first.
        chain.clear();
        for (std::size_t g = start; g != TileGroup::kNone; g = groups[g].parent) {
            if (g >= n) throw Error("choose_group_levels: parent index " + std::to_string(g) + " out of range");
            if (state[g] == 2) break;
            if (state[g] == 1) throw Error("choose_group_levels: groups' parents form a cycle");
            state[g] = 1;
            chain.push_back(g);
        }
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
            const std::size_t g = *it;
            const std::size_t p = groups[g].parent;
            if (p != TileGroup::kNone && (covered[p] || level[p] > 0))
                covered[g] = 1;
            else {
                level[g] = choose_level(groups[g].levels, px_per_m[g], max_px);
                if (level[g] == 0 && stands_in[g] && !groups[g].levels.empty()) level[g] = 1;
            }
            state[g] = 2;
        }
    }
    return level;
}

std::vector<std::uint8_t> groups_drawn_own_only(std::span<const TileGroup> groups, std::span<const std::size_t> level,
                                                std::span<const std::uint8_t> visible) {
    const std::size_t n = groups.size();
    if (level.size() != n || visible.size() != n)
        throw Error("groups_drawn_own_only: " + std::to_string(level.size()) + " levels and " +
                    std::to_string(visible.size()) + " visibilities for " + std::to_string(n) + " groups");
    const auto own_level = [&](std::size_t g) -> const TileMeshLevel* {
        if (level[g] == 0) return nullptr;
        if (level[g] > groups[g].levels.size())
            throw Error("groups_drawn_own_only: level " + std::to_string(level[g]) + " of group " + std::to_string(g) +
                        " out of range");
        const TileMeshLevel& l = groups[g].levels[level[g] - 1];
        return l.own_triangles > 0 ? &l : nullptr;
    };
    std::vector<std::uint8_t> out(n, 0);
    for (std::size_t g = 0; g < n; ++g) {
        const TileMeshLevel* l = own_level(g);
        if (!l) continue;
        bool own_only = true;
        for (int slot = 0; slot < 27 && own_only; ++slot) {
            if (!(l->joins & (1u << slot))) continue;
            const std::size_t nb = groups[g].neighbours[static_cast<std::size_t>(slot)];
            if (nb != TileGroup::kNone && nb >= n)
                throw Error("groups_drawn_own_only: neighbour index " + std::to_string(nb) + " out of range");
            own_only = nb != TileGroup::kNone && visible[nb] != 0 && own_level(nb) != nullptr;
        }
        out[g] = own_only ? 1 : 0;
    }
    return out;
}

bool level_within_bound(const TileGroup& group, std::size_t level, double px_per_m, double max_px) {
    if (level == 0 || level > group.levels.size()) return false;
    return group.levels[level - 1].error_m * px_per_m <= max_px;
}

bool wants_detail(const TileGroup& group, std::size_t level, double px_per_m, double max_px, bool stands_in) {
    if (level == 0 || level > group.levels.size() || !stands_in) return false;
    return !level_within_bound(group, level, px_per_m, max_px);
}

}  // namespace tridex::renderer
