// compute/runtime/site_strokes.hpp - whose strokes a shared session's undo history holds, and whether a person may
// undo or redo: personal undo takes back only the asker's own newest stroke, and only while nobody else has carved
// since that stroke began (docs/undo.md, "Shared sessions").
#pragma once

#include <cstdint>
#include <array>
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

/// The sites of the sculpt thread's strokes. Each stroke that changed the model (an undo step) is tagged with its site
/// and the newest undo step that existed when that site's gesture began (a gesture spans the strokes another site's
/// cuts split it into: compute::SiteSweeps). The undo history is one stack, so a site may undo only its own newest
/// step, and only when no other site's step came after its gesture began; strokes that changed nothing (a tool
/// resting in material) never stand in the way. Redo likewise needs the newest undone step to be its own. With one
/// site nothing is ever refused. Not thread-safe (the sculpt thread's).
class SiteStrokes {
public:
    /// The per-site sweeps and stroke closes of the stream.
    compute::SiteSweeps& sweeps() { return sweeps_; }
    const compute::SiteSweeps& sweeps() const { return sweeps_; }
    /// A stroke opened with the sweeps of sweeps().open_site(): remembers its site and, unless it continues an
    /// interrupted gesture, that its gesture begins now.
    void opened();
    /// The open stroke closed as `serial`; `kept`: it became an undo step (it changed the model). Tells sweeps()
    /// whether its gesture goes on (`by_site`: the other site whose sample or request closed it) or ended.
    void closed(std::uint64_t serial, bool kept, std::optional<std::uint8_t> by_site);
    /// The site whose step keeps `site` from undoing step `serial` (the newest undo step): its owner when it is not
    /// `site`'s, else the first other site with a step after `site`'s gesture began; nullopt when it may (or serial is
    /// 0: nothing to undo).
    std::optional<std::uint8_t> blocks_undo(std::uint8_t site, std::uint64_t serial) const;
    /// True when steps `a` and `b` are parts of one site's gesture (another site's cuts split it): one undo or redo
    /// takes them together.
    bool same_gesture(std::uint64_t a, std::uint64_t b) const;
    /// The site whose undone stroke is next to redo when it is not `site`'s own (serial: the newest redo step),
    /// nullopt when `site` may redo it (or serial is 0).
    std::optional<std::uint8_t> blocks_redo(std::uint8_t site, std::uint64_t serial) const;

private:
    struct Tag {
        std::uint8_t site = 0;
        std::uint64_t since = 0;  // the newest undo step's serial when the site's gesture began (0: none)
    };
    compute::SiteSweeps sweeps_;
    Tag open_;
    std::array<std::uint64_t, kMaxSites> gesture_since_{};  // per site: Tag::since of its current gesture
    std::uint64_t last_kept_ = 0;                            // the newest step's serial
    std::map<std::uint64_t, Tag> steps_;  // serial -> tag of every step kept; a step not found is site 0's
};

}  // namespace tridex::app
