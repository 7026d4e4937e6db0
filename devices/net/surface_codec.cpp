// devices/net/surface_codec.cpp - sparse encoding of the active-surface windows.
#include "devices/net/surface_codec.hpp"

#include "devices/net/wire_io.hpp"

namespace tridex::devices::net {

namespace {
constexpr int kW = ActiveSurface::kWindow;
constexpr int kI = ActiveSurface::kMaxIntervals;
}  // namespace

void encode_surface(Header h, const ActiveSurface& s, std::vector<std::uint8_t>& out) {
    h.type = MsgType::kSurface;
    encode_header(h, out);
    Writer w(out);
    w.u64(s.sequence);
    w.vec3(s.origin_m);
    w.f64(s.cell_m);
    for (int a = 0; a < 3; ++a) w.u32(static_cast<std::uint32_t>(s.nodes[a]));
    w.vec3(s.centre_m);
    for (const ActiveSurface::Window& win : s.sets) {
        w.u32(static_cast<std::uint32_t>(win.u0));
        w.u32(static_cast<std::uint32_t>(win.v0));
        w.u32(static_cast<std::uint32_t>(win.stride));
        w.u8(static_cast<std::uint8_t>(win.nu));
        w.u8(static_cast<std::uint8_t>(win.nv));
        w.u8(win.truncated ? 1 : 0);
        for (int iv = 0; iv < win.nv; ++iv)
            for (int iu = 0; iu < win.nu; ++iu) {
                const int idx = iu + kW * iv;
                const int c = win.count[idx];
                w.u8(static_cast<std::uint8_t>(c));
                for (int k = 0; k < c; ++k) {
                    w.f32(win.depth[(idx * kI + k) * 2]);
                    w.f32(win.depth[(idx * kI + k) * 2 + 1]);
                    w.u8(win.material[idx * kI + k]);
                }
            }
    }
}

DropReason decode_surface(const std::uint8_t* p, std::size_t n, ActiveSurface& out) {
    Reader r(p + kHeaderBytes, n - kHeaderBytes);
    out.sequence = r.u64();
    out.origin_m = r.vec3();
    out.cell_m = r.f64();
    for (int a = 0; a < 3; ++a) out.nodes[a] = static_cast<std::int32_t>(r.u32());
    out.centre_m = r.vec3();
    if (r.failed()) return DropReason::kBadLength;
    if (r.non_finite()) return DropReason::kNonFinite;
    if (!(out.cell_m > 0.0) || out.nodes[0] < 0 || out.nodes[1] < 0 || out.nodes[2] < 0) return DropReason::kOutOfRange;
    for (ActiveSurface::Window& win : out.sets) {
        win.u0 = static_cast<std::int32_t>(r.u32());
        win.v0 = static_cast<std::int32_t>(r.u32());
        win.stride = static_cast<std::int32_t>(r.u32());
        win.nu = r.u8();
        win.nv = r.u8();
        const std::uint8_t trunc = r.u8();
        if (r.failed()) return DropReason::kBadLength;
        if (win.nu > kW || win.nv > kW || win.stride < 1 || trunc > 1) return DropReason::kOutOfRange;
        win.truncated = trunc != 0;
        win.count.fill(0);
        for (int iv = 0; iv < win.nv; ++iv)
            for (int iu = 0; iu < win.nu; ++iu) {
                const int idx = iu + kW * iv;
                const int c = r.u8();
                if (c > kI) return DropReason::kOutOfRange;
                win.count[idx] = static_cast<std::uint8_t>(c);
                for (int k = 0; k < c; ++k) {
                    win.depth[(idx * kI + k) * 2] = r.f32();
                    win.depth[(idx * kI + k) * 2 + 1] = r.f32();
                    win.material[idx * kI + k] = r.u8();
                }
                if (r.failed()) return DropReason::kBadLength;
            }
    }
    if (r.failed() || !r.at_end()) return DropReason::kBadLength;
    return r.non_finite() ? DropReason::kNonFinite : DropReason::kNone;
}

}  // namespace tridex::devices::net
