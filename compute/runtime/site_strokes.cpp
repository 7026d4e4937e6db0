// compute/runtime/site_strokes.cpp - the sites of the undo history's strokes, for personal undo.
#include "compute/runtime/site_strokes.hpp"

namespace tridex::app {

void SiteStrokes::opened() {
    open_.site = sweeps_.open_site();
    open_.interrupted_by = sweeps_.interrupted_by(open_.site);
}

void SiteStrokes::closed(std::uint64_t serial, std::optional<std::uint8_t> by_site) {
    if (serial != 0 && (open_.site != 0 || open_.interrupted_by)) tags_[serial] = open_;  // site 0's plain strokes: no entry
    sweeps_.stroke_closed(by_site);
    open_ = Tag{};
}

const SiteStrokes::Tag* SiteStrokes::tag(std::uint64_t serial) const {
    const auto it = tags_.find(serial);
    return it == tags_.end() ? nullptr : &it->second;
}

std::optional<std::uint8_t> SiteStrokes::blocks_undo(std::uint8_t site, std::uint64_t serial) const {
    if (serial == 0) return std::nullopt;
    const Tag* t = tag(serial);
    const std::uint8_t owner = t ? t->site : 0;
    if (owner != site) return owner;
    if (t && t->interrupted_by) return t->interrupted_by;
    return std::nullopt;
}

std::optional<std::uint8_t> SiteStrokes::blocks_redo(std::uint8_t site, std::uint64_t serial) const {
    if (serial == 0) return std::nullopt;
    const Tag* t = tag(serial);
    const std::uint8_t owner = t ? t->site : 0;
    return owner != site ? std::optional<std::uint8_t>(owner) : std::nullopt;
}

}  // namespace tridex::app
