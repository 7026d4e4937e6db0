// app/menu/pie_menu.hpp - a pie (marking) menu at the hand: a ring of slices in the plane facing the head, chosen by
// the hand's direction from where it opened; quick flicks choose without the ring being shown.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/material_palette.hpp"
#include "core/math.hpp"

namespace tridex::app {

/// One slice of a ring: a command (action set) or a sub-ring (children set); neither = "Cancel" (closes the menu).
struct MenuItem {
    std::string label;               ///< drawn on the slice
    std::string glyph;               ///< drawn above the label (ASCII); "" = none
    std::string action;              ///< an action name of builtin_actions(); "" for a sub-ring or Cancel
    std::vector<MenuItem> children;  ///< a sub-ring's slices (at most 12)
    bool branch() const { return !children.empty(); }
};

/// The default menu, with every action a desk key has: Operation (subtract, union, paint, push, smooth, pull, grab),
/// Tool (larger, Colour: materials 1..7 labelled with `palette`'s names, smaller, Cancel), Redo, Save, End (End
/// session, Cancel), View (re-centre, swap eyes, occlusion), Undo and Next op; the eight top slices clockwise from 12
/// o'clock. Other labels and glyphs come from builtin_actions().
MenuItem default_menu(const MaterialPalette& palette = default_material_palette());

/// How the menu reads the hand (lengths in the frame of the positions given, normally world m).
struct PieMenuSettings {
    double radius_m = 0.05;       ///< ring radius: past it in a sub-ring's slice, that sub-ring opens at the hand
    double dead_radius_m = 0.012; ///< nothing is highlighted nearer the centre than this
    double show_delay_s = 0.25;   ///< the ring is drawn once the button is held this long (a flick before: unseen)
};

/// What one ring shows: its slices around `centre_m` in the plane spanned by `right` and `up` (facing the head).
struct RingView {
    Vec3 centre_m{0.0};
    Vec3 right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0}, normal{0.0, 0.0, 1.0};  ///< unit; normal points at the head
    double radius_m = 0.05, dead_radius_m = 0.012;
    const MenuItem* node = nullptr;  ///< the ring's item (its children are the slices)
    int highlighted = -1;            ///< slice under the hand's direction, -1: none
};

/// The result of releasing the menu button.
struct MenuChoice {
    std::string action;      ///< the chosen action ("" = Cancel was chosen)
    std::string label;       ///< the chosen slice's label
    bool flick = false;      ///< chosen before the ring was shown (a practised mark)
};

/// The pie menu's state machine (one thread, the frame loop's). Slice k of a ring of n is centred at 12 o'clock
/// turned k * 360/n degrees clockwise, as seen from the head. Press the menu button: open() at the hand. Move the
/// hand: the slice in its direction from the ring's centre lights (update()); past radius_m in a sub-ring's slice,
/// that sub-ring opens centred at the hand (so a practised two-stroke mark reaches its slices too). Release: the lit
/// command is chosen; a lit sub-ring stays open at the hand for a second click; a release in the centre right after
/// opening (a click) keeps the ring open too, and then a press and release chooses (in the centre: closes). Positions
/// and times must be finite; non-finite ones are ignored. Not thread-safe.
class PieMenu {
public:
    /// Throws tridex::Error when settings are not finite, dead_radius_m is not in (0, radius_m), or show_delay_s < 0.
    explicit PieMenu(PieMenuSettings settings = {});

    /// Opens `root` (which must outlive the open menu) at hand_m facing head_m at time t_s (s), its radii the
    /// settings' times `size` (> 0: the positions' units per world m, e.g. 1 / the scene's scale). The plane's up is
    /// the world's +y made perpendicular to the hand-to-head direction (+z when that is vertical). Does nothing when
    /// open already, `root` has no slices, or input is not finite and positive.
    void open(const MenuItem& root, const Vec3& hand_m, const Vec3& head_m, double t_s, double size = 1.0);
    /// The hand moved: lights the slice in its direction; may open a sub-ring (see above).
    void update(const Vec3& hand_m, double t_s);
    /// The menu button went down again while the menu stays open (after a click): the next release chooses.
    void press(const Vec3& hand_m, double t_s);
    /// The menu button was released: the choice, or nullopt when the menu closed with nothing chosen or stays open.
    std::optional<MenuChoice> release(const Vec3& hand_m, double t_s);
    /// Closes without a choice (the device was lost, the session ends).
    void close();

    bool is_open() const { return open_; }
    /// True once the ring is drawn (held past show_delay_s, or kept open by a click).
    bool shown(double t_s) const;
    /// The ring in use (valid while open).
    const RingView& ring() const { return ring_; }
    /// The slice indices from the root to the ring in use ([] = the root's ring).
    const std::vector<std::uint8_t>& path() const { return path_; }
    /// The slice index of hand_m in the current ring, or -1 in the dead zone / closed / non-finite.
    int slice_at(const Vec3& hand_m) const;
    /// The settings.
    const PieMenuSettings& settings() const { return settings_; }

private:
    void open_ring(const MenuItem& node, const Vec3& centre_m);

    PieMenuSettings settings_;
    RingView ring_;
    std::vector<std::uint8_t> path_;
    bool open_ = false;
    bool sticky_ = false;      // kept open by a click or a sub-ring chosen by release: the next release chooses
    bool pressed_again_ = false;
    double opened_at_s_ = 0.0;
};

}  // namespace tridex::app
