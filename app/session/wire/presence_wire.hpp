// app/session/wire/presence_wire.hpp - a site's presence, names, colours and site numbers in a message's fields
// (a shared session's presence message, a cluster's frame message).
#pragma once

#include <cstdint>
#include <string>

#include "app/session/runtime/site_presence.hpp"
#include "app/session/wire/message_io.hpp"

namespace tridex::app {

/// Longest person's name, bytes.
inline constexpr std::size_t kMaxSiteName = 64;

/// Writes `p`'s fields: site, gone, name, colour, tool pose and radius, head flag, and the head's pose and size when
/// tracked.
void write_presence(MessageWriter& w, const SitePresence& p);
/// Reads what write_presence wrote; fails the reader (tridex::Error "<from>: <field>: <what>") on a site out of range,
/// a bad name or colour, a non-finite pose, a tool radius outside [0, 1] m or a head size outside (0, 100] m.
SitePresence read_presence(MessageReader& r);

/// A person's name: 1..kMaxSiteName bytes (0.. when may_be_empty), no control characters; fails the reader otherwise.
std::string read_site_name(MessageReader& r, const char* field, bool may_be_empty);
/// An sRGB colour, each channel 0..1; fails the reader otherwise.
Vec3 read_colour(MessageReader& r, const char* field);
/// A site number 0..kMaxSites-1; fails the reader otherwise.
std::uint8_t read_site(MessageReader& r, const char* field);

}  // namespace tridex::app
