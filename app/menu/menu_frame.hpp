// app/menu/menu_frame.hpp - what the pie menu shows at one moment, as plain data: drawn by the session, sent to a
// cluster's render ranks with each frame, and kept in a recording as a track so that a replay shows the same menu.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "app/menu/pie_menu.hpp"
#include "app/menu/pie_menu_mesh.hpp"
#include "renderer/stereo/stereo_renderer.hpp"

namespace tridex::app {

/// The menu as drawn (positions in the scene's frame, m). Not shown: nothing is drawn, the rest is zero.
struct MenuFrame {
    bool shown = false;
    Vec3 centre_m{0.0}, right{1.0, 0.0, 0.0}, up{0.0, 1.0, 0.0}, normal{0.0, 0.0, 1.0};  ///< RingView's
    double radius_m = 0.0, dead_radius_m = 0.0;
    std::vector<std::uint8_t> path;  ///< slice indices from the root to the ring drawn (PieMenu::path)
    int highlighted = -1;            ///< the lit slice, -1: none
    std::string status;              ///< the lines below the ring
    bool operator==(const MenuFrame&) const = default;
};

/// What `menu` shows at time t_s (PieMenu::shown), with `status` below it.
MenuFrame menu_frame_of(const PieMenu& menu, double t_s, const std::string& status);

/// The ring of `f` in the menu `root` (RingView::node null when not shown, or its path or lit slice is not in the
/// menu: a frame from another build's menu draws nothing).
RingView ring_of(const MenuFrame& f, const MenuItem& root);

/// The meshes of `f` (pie_menu_pieces of its ring and status); none when nothing is shown.
std::vector<MenuPiece> menu_frame_pieces(const MenuFrame& f, const MenuItem& root);

/// The menu's meshes as scene objects, kept from frame to frame: rebuilt only when what the menu shows changes. The
/// renderer uploads an object's mesh again when its pointer changes (SceneObject), and a rebuild makes the new meshes
/// while the old ones still exist, so their pointers differ exactly when their content does; an unchanged menu costs
/// no new meshes and no upload. One thread (the one that draws).
class MenuDrawing {
public:
    /// Appends the objects that draw `f` in the menu `root` (none when not shown) to `objects`: flat colours, both
    /// eyes, on top of the scene (SceneObject::on_top). They point into this object: keep it alive and unchanged
    /// until the frame is drawn.
    void append(const MenuFrame& f, const MenuItem& root, std::vector<renderer::SceneObject>& objects);

private:
    MenuFrame drawn_;
    std::vector<MenuPiece> pieces_;
};

/// The menu's frames over a session, one entry per change (device time, s, and the frame), bounded: past kMaxEntries
/// changes it keeps the first ones and counts the rest. One thread.
class MenuTrack {
public:
    static constexpr std::size_t kMaxEntries = 200000;  ///< changes kept (a change takes about 200 bytes)
    /// Adds the frame drawn at device time t_s when it differs from the last one added (non-finite t_s: ignored).
    void add(double t_s, const MenuFrame& f);
    /// The frame in effect at t_s: the last added at or before it (not shown before the first).
    MenuFrame at(double t_s) const;
    std::size_t size() const { return entries_.size(); }  ///< changes kept
    std::uint64_t dropped() const { return dropped_; }    ///< changes past kMaxEntries
    /// The track as JSON text, an array of {t_s, shown, centre_m, right, up, normal, radius_m, dead_radius_m, path,
    /// highlighted, status}; "" when empty (a recording then has no menu).
    std::string to_json_text() const;
    /// Reads to_json_text()'s form; throws tridex::Error "<where>: menu[K].<field>: <what>" on a malformed entry
    /// (not an object, a missing or non-finite number, times that decrease, a path entry out of 0..31).
    static MenuTrack from_json_text(const std::string& text, const std::string& where);

private:
    struct Entry {
        double t_s = 0.0;
        MenuFrame frame;
    };
    std::vector<Entry> entries_;
    std::uint64_t dropped_ = 0;
};

}  // namespace tridex::app
