// compute/journal/journal_format.cpp - bit-exact ToolSample encoding of the session journal.
#include "compute/journal/journal_format.hpp"

namespace tridex::compute {

void encode_sample(const ToolSample& s, unsigned char* out) {
    put_f64(out + 0, s.t_s);
    for (int k = 0; k < 3; ++k) put_f64(out + 8 + 8 * k, s.position[k]);
    for (int k = 0; k < 3; ++k) put_f64(out + 32 + 8 * k, s.surface_m[k]);
    put_f64(out + 56, s.orientation.w);
    put_f64(out + 64, s.orientation.x);
    put_f64(out + 72, s.orientation.y);
    put_f64(out + 80, s.orientation.z);
    put_f64(out + 88, s.tool.radius_m);
    put_f64(out + 96, s.tool.length_m);
    put_u32(out + 104, s.tool.mesh_id);
    put_u32(out + 108, s.buttons);
    out[112] = static_cast<unsigned char>(s.tool.kind);
    out[113] = static_cast<unsigned char>(s.op);
    out[114] = s.material;
    out[115] = static_cast<unsigned char>((s.symmetry.mirrors & 7u) | (s.symmetry.radial_axis & 3u) << 4);
    put_u16(out + 116, s.symmetry.radial_copies);
    out[118] = s.site;
    out[119] = 0;
}

bool decode_sample(const unsigned char* in, ToolSample& s) {
    if (in[112] > static_cast<unsigned char>(ToolKind::kMesh) ||
        in[113] > static_cast<unsigned char>(ToolOp::kGrab) || (in[115] & 0xc8u) != 0 || in[118] >= kMaxSites || in[119] != 0)
        return false;
    s.symmetry.mirrors = static_cast<std::uint8_t>(in[115] & 7u);
    s.symmetry.radial_axis = static_cast<std::uint8_t>((in[115] >> 4) & 3u);
    s.symmetry.radial_copies = get_u16(in + 116);
    if (!valid_symmetry(s.symmetry)) return false;
    s.t_s = get_f64(in + 0);
    for (int k = 0; k < 3; ++k) s.position[k] = get_f64(in + 8 + 8 * k);
    for (int k = 0; k < 3; ++k) s.surface_m[k] = get_f64(in + 32 + 8 * k);
    s.orientation.w = get_f64(in + 56);
    s.orientation.x = get_f64(in + 64);
    s.orientation.y = get_f64(in + 72);
    s.orientation.z = get_f64(in + 80);
    s.tool.radius_m = get_f64(in + 88);
    s.tool.length_m = get_f64(in + 96);
    s.tool.mesh_id = get_u32(in + 104);
    s.buttons = get_u32(in + 108);
    s.tool.kind = static_cast<ToolKind>(in[112]);
    s.op = static_cast<ToolOp>(in[113]);
    s.material = in[114];
    s.site = in[118];
    return true;
}

}  // namespace tridex::compute
