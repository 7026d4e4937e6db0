// app/session/wire/presence_wire.cpp - a site's presence in a message's fields.
#include "app/session/wire/presence_wire.hpp"

#include "core/tool_sample.hpp"

namespace tridex::app {

void write_presence(MessageWriter& w, const SitePresence& p) {
    w.u8(p.site);
    w.u8(p.gone ? 1 : 0);
    w.text(p.name);
    w.vec3(p.colour);
    w.pose(p.tool);
    w.f64(p.tool_radius_m);
    w.u8(p.head_tracked ? 1 : 0);
    if (p.head_tracked) {
        w.pose(p.head);
        w.f64(p.head_size_m);
    }
}

SitePresence read_presence(MessageReader& r) {
    SitePresence p;
    p.site = read_site(r, "site");
    const std::uint8_t gone = r.u8("gone");
    if (gone > 1) r.fail("gone", "not 0 or 1");
    p.gone = gone != 0;
    p.name = read_site_name(r, "name", true);
    p.colour = read_colour(r, "colour");
    p.tool = r.pose("tool");
    p.tool_radius_m = r.f64("tool_radius_m");
    if (p.tool_radius_m < 0.0 || p.tool_radius_m > 1.0) r.fail("tool_radius_m", "must be in [0, 1] m");
    const std::uint8_t tracked = r.u8("head_tracked");
    if (tracked > 1) r.fail("head_tracked", "not 0 or 1");
    p.head_tracked = tracked != 0;
    if (p.head_tracked) {
        p.head = r.pose("head");
        p.head_size_m = r.f64("head_size_m");
        if (!(p.head_size_m > 0.0 && p.head_size_m <= 100.0)) r.fail("head_size_m", "must be in (0, 100] m");
    }
    return p;
}

std::string read_site_name(MessageReader& r, const char* field, bool may_be_empty) {
    std::string s = r.text(field);
    if (s.size() > kMaxSiteName || (!may_be_empty && s.empty()))
        r.fail(field, "a name is 1.." + std::to_string(kMaxSiteName) + " bytes");
    for (const char c : s)
        if (static_cast<unsigned char>(c) < 0x20) r.fail(field, "a control character in a name");
    return s;
}

Vec3 read_colour(MessageReader& r, const char* field) {
    const Vec3 c = r.vec3(field);
    for (int k = 0; k < 3; ++k)
        if (c[k] < 0.0 || c[k] > 1.0) r.fail(field, "a colour's channels are 0..1");
    return c;
}

std::uint8_t read_site(MessageReader& r, const char* field) {
    const std::uint8_t s = r.u8(field);
    if (s >= kMaxSites) r.fail(field, "site " + std::to_string(s) + " is not 0.." + std::to_string(kMaxSites - 1));
    return s;
}

}  // namespace tridex::app
