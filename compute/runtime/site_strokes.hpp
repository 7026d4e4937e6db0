// compute/runtime/site_strokes.hpp - whose strokes a shared session's undo history holds, and whether a person may
// undo or redo: personal undo takes back only the asker's own newest stroke, and only while nobody else has carved
// since that stroke began (docs/undo.md, "Shared sessions").
#pragma once

#include <cstdint>
#include <map>
#include <optional>

#include "compute/runtime/site_intake.hpp"
#include "compute/tools/site_sweeps.hpp"

namespace tridex::app {

/// A request the sculpt thread refused because it would take back another site's work (SculptThread::
/// observe_refusals, SculptStats::refusals).
struct SculptRefusal {
    SculptRequest request = SculptRequest::kUndo;  ///< kUndo or kRedo
    std::uint8_t site = 0;     ///< who asked
    std::uint8_t by_site = 0;  ///< whose stroke stands in the way
    std::uint64_t serial = 0;  ///< the stroke the history would have undone or redone (UndoHistory serial)
};

/// The sites of the sculpt thread's strokes. Each closed stroke is tagged with its site and, when it continues a
/// gesture another site's stroke interrupted (compute::SiteSweeps), that site. The undo history is one stack, so a
/// site may undo only when the newest step is its own and began no earlier than every other site's step: its own
/// and not a continuation. Redo likewise needs the newest undone step to be its own. With one site nothing is ever
/// refused. Not thread-safe (the sculpt thread's).
class SiteStrokes {
public:
    /// The per-site sweeps and stroke closes of the stream.
    compute::SiteSweeps& sweeps() { return sweeps_; }
    const compute::SiteSweeps& sweeps() const { return sweeps_; }
    /// A stroke opened with the sweeps of sweeps().open_site(): remembers its site and whether it continues an
    /// interrupted gesture.
    void opened();
    /// The open stroke closed as `serial` (0: it changed nothing and no step was kept): tags the step, and tells
    /// sweeps() whether its gesture goes on (`by_site`: the other site whose sample or request closed it) or ended.
    void closed(std::uint64_t serial, std::optional<std::uint8_t> by_site);
    /// The site whose stroke keeps `site` from undoing step `serial` (the newest undo step), nullopt when it may (or
    /// serial is 0: nothing to undo).
    std::optional<std::uint8_t> blocks_undo(std::uint8_t site, std::uint64_t serial) const;
    /// The site whose undone stroke is next to redo when it is not `site`'s own (serial: the newest redo step),
    /// nullopt when `site` may redo it (or serial is 0).
    std::optional<std::uint8_t> blocks_redo(std::uint8_t site, std::uint64_t serial) const;

private:
    struct Tag {
        std::uint8_t site = 0;
        std::optional<std::uint8_t> interrupted_by;
    };
    compute::SiteSweeps sweeps_;
    Tag open_;
    std::map<std::uint64_t, Tag> tags_;  // serial -> tag; a step not found is site 0's (a history resumed from a file)
    const Tag* tag(std::uint64_t serial) const;
};

}  // namespace tridex::app
