// app/menu/menu_frame.cpp - the menu as plain data, and its track over a session.
#include "app/menu/menu_frame.hpp"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace tridex::app {

namespace {

nlohmann::json vec_json(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

Vec3 vec_from(const nlohmann::json& j, const std::string& at) {
    if (!j.is_array() || j.size() != 3) throw Error(at + ": must be [x, y, z]");
    Vec3 v;
    for (int i = 0; i < 3; ++i) {
        if (!j[static_cast<std::size_t>(i)].is_number()) throw Error(at + ": must be [x, y, z] numbers");
        v[i] = j[static_cast<std::size_t>(i)].get<double>();
    }
    if (!is_finite(v)) throw Error(at + ": is not finite");
    return v;
}

double number_from(const nlohmann::json& o, const char* key, const std::string& at) {
    const auto it = o.find(key);
    if (it == o.end() || !it->is_number()) throw Error(at + "." + key + ": missing or not a number");
    const double d = it->get<double>();
    if (!std::isfinite(d)) throw Error(at + "." + key + ": is not finite");
    return d;
}

}  // namespace

MenuFrame menu_frame_of(const PieMenu& menu, double t_s, const std::string& status) {
    MenuFrame f;
    if (!menu.shown(t_s) || !menu.ring().node) return f;
    const RingView& r = menu.ring();
    f.shown = true;
    f.centre_m = r.centre_m;
    f.right = r.right;
    f.up = r.up;
    f.normal = r.normal;
    f.radius_m = r.radius_m;
    f.dead_radius_m = r.dead_radius_m;
    f.path = menu.path();
    f.highlighted = r.highlighted;
    f.status = status;
    return f;
}

RingView ring_of(const MenuFrame& f, const MenuItem& root) {
    RingView r;
    if (!f.shown) return r;
    const MenuItem* node = &root;
    for (const std::uint8_t k : f.path) {
        if (k >= node->children.size() || !node->children[k].branch()) return r;
        node = &node->children[k];
    }
    if (f.highlighted >= static_cast<int>(node->children.size())) return r;
    r.centre_m = f.centre_m;
    r.right = f.right;
    r.up = f.up;
    r.normal = f.normal;
    r.radius_m = f.radius_m;
    r.dead_radius_m = f.dead_radius_m;
    r.node = node;
    r.highlighted = f.highlighted;
    return r;
}

std::vector<MenuPiece> menu_frame_pieces(const MenuFrame& f, const MenuItem& root) {
    const RingView r = ring_of(f, root);
    return r.node ? pie_menu_pieces(r, f.status) : std::vector<MenuPiece>{};
}

void MenuDrawing::append(const MenuFrame& f, const MenuItem& root, std::vector<renderer::SceneObject>& objects) {
    if (!(f == drawn_)) {
        pieces_ = menu_frame_pieces(f, root);  // made before the old meshes are freed: new pointers
        drawn_ = f;
    }
    for (const MenuPiece& p : pieces_) objects.push_back({&p.mesh, p.colour, 0b11, false, true});
}

void MenuTrack::add(double t_s, const MenuFrame& f) {
    if (!std::isfinite(t_s)) return;
    if (entries_.empty() ? !f.shown : entries_.back().frame == f) return;
    if (entries_.size() >= kMaxEntries) {
        ++dropped_;
        return;
    }
    // Device time never runs back within a session; a frame drawn from an older view keeps the newest time.
    const double t = entries_.empty() ? t_s : std::max(t_s, entries_.back().t_s);
    entries_.push_back(Entry{t, f});
}

MenuFrame MenuTrack::at(double t_s) const {
    const auto it = std::upper_bound(entries_.begin(), entries_.end(), t_s,
                                     [](double t, const Entry& e) { return t < e.t_s; });
    return it == entries_.begin() ? MenuFrame{} : std::prev(it)->frame;
}

std::string MenuTrack::to_json_text() const {
    if (entries_.empty()) return "";
    nlohmann::json a = nlohmann::json::array();
    for (const Entry& e : entries_) {
        const MenuFrame& f = e.frame;
        a.push_back({{"t_s", e.t_s}, {"shown", f.shown}, {"centre_m", vec_json(f.centre_m)}, {"right", vec_json(f.right)},
                     {"up", vec_json(f.up)}, {"normal", vec_json(f.normal)}, {"radius_m", f.radius_m},
                     {"dead_radius_m", f.dead_radius_m}, {"path", f.path}, {"highlighted", f.highlighted},
                     {"status", f.status}});
    }
    return a.dump();
}

MenuTrack MenuTrack::from_json_text(const std::string& text, const std::string& where) {
    MenuTrack t;
    if (text.empty()) return t;
    nlohmann::json a;
    try {
        a = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) {
        throw Error(where + ": menu: not valid JSON");
    }
    if (!a.is_array()) throw Error(where + ": menu: must be an array");
    for (std::size_t k = 0; k < a.size(); ++k) {
        const std::string at = where + ": menu[" + std::to_string(k) + "]";
        const nlohmann::json& o = a[k];
        if (!o.is_object()) throw Error(at + ": must be an object");
        Entry e;
        e.t_s = number_from(o, "t_s", at);
        if (!t.entries_.empty() && e.t_s < t.entries_.back().t_s) throw Error(at + ".t_s: decreases");
        MenuFrame& f = e.frame;
        f.shown = o.value("shown", false);
        if (f.shown) {
            f.centre_m = vec_from(o.value("centre_m", nlohmann::json()), at + ".centre_m");
            f.right = vec_from(o.value("right", nlohmann::json()), at + ".right");
            f.up = vec_from(o.value("up", nlohmann::json()), at + ".up");
            f.normal = vec_from(o.value("normal", nlohmann::json()), at + ".normal");
            f.radius_m = number_from(o, "radius_m", at);
            f.dead_radius_m = number_from(o, "dead_radius_m", at);
            f.highlighted = static_cast<int>(number_from(o, "highlighted", at));
            const nlohmann::json p = o.value("path", nlohmann::json::array());
            if (!p.is_array()) throw Error(at + ".path: must be an array");
            for (const nlohmann::json& i : p) {
                if (!i.is_number_integer() || i.get<int>() < 0 || i.get<int>() > 31)
                    throw Error(at + ".path: entries must be slice indices 0..31");
                f.path.push_back(static_cast<std::uint8_t>(i.get<int>()));
            }
            const nlohmann::json s = o.value("status", nlohmann::json(""));
            f.status = s.is_string() ? s.get<std::string>() : "";
        }
        t.entries_.push_back(std::move(e));
    }
    return t;
}

}  // namespace tridex::app
