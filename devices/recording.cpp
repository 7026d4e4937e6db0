// devices/recording.cpp - the "TRDXREC" binary format (little-endian, field by field), its writer, its
// validating reader and the CSV export.
#include "devices/recording.hpp"
#include "devices/recording_poses.hpp"

#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <exception>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/le_bytes.hpp"
#include "core/text/printable.hpp"
#include "core/tool_sample.hpp"

namespace tridex::devices {

namespace {

constexpr std::uint64_t kOpenCount = std::numeric_limits<std::uint64_t>::max();
constexpr double kTwoPi = 6.283185307179586476925286766559;

// ---- little-endian encoding ----
class Encoder {
public:
    explicit Encoder(unsigned char* p) : p_(p) {}
    void u8(std::uint8_t v) { *p_++ = v; }
    void u32(std::uint32_t v) {
        put_u32(p_, v);
        p_ += 4;
    }
    void u64(std::uint64_t v) {
        put_u64(p_, v);
        p_ += 8;
    }
    void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
    void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
    void vec(const Vec3& v) { f64(v.x), f64(v.y), f64(v.z); }

private:
    unsigned char* p_;
};

class Decoder {
public:
    explicit Decoder(const unsigned char* p) : p_(p) {}
    std::uint8_t u8() { return *p_++; }
    std::uint32_t u32() {
        const std::uint32_t v = get_u32(p_);
        p_ += 4;
        return v;
    }
    std::uint64_t u64() {
        const std::uint64_t v = get_u64(p_);
        p_ += 8;
        return v;
    }
    std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
    double f64() { return std::bit_cast<double>(u64()); }
    Vec3 vec() {
        Vec3 v;
        v.x = f64(), v.y = f64(), v.z = f64();
        return v;
    }

private:
    const unsigned char* p_;
};

void encode_tick(const RecordedTick& t, unsigned char* out) {
    Encoder e(out);
    e.f64(t.t_s);
    e.f64(t.device.t_s);
    e.vec(t.device.pose.position);
    e.f64(t.device.pose.orientation.w), e.f64(t.device.pose.orientation.x);
    e.f64(t.device.pose.orientation.y), e.f64(t.device.pose.orientation.z);
    e.vec(t.device.velocity_m_s);
    e.u32(t.device.buttons);
    e.vec(t.wand_centre_m);
    e.vec(t.rotation_axis);
    e.f64(t.rotation_angle_rad);
    e.vec(t.top_m), e.vec(t.bottom_m);
    e.vec(t.top_contact_m), e.vec(t.bottom_contact_m);
    e.f64(t.top_deviation_m), e.f64(t.bottom_deviation_m);
    e.vec(t.top_force_n), e.vec(t.bottom_force_n), e.vec(t.force_n);
    e.vec(t.torque_nm);
    e.i32(t.top_collision_id), e.i32(t.bottom_collision_id);
    e.u32(t.buttons);
    e.u8(t.tool_mode);
    e.u8(t.valid);
    e.u8(t.op);
    e.u8(t.material);
    e.u8(static_cast<std::uint8_t>(t.tool.kind));
    e.f64(t.tool.radius_m);
    e.f64(t.tool.length_m);
    e.u32(symmetry_bits(t.symmetry));
    e.u8(static_cast<std::uint8_t>(t.workpiece < 0 ? 0 : t.workpiece));
}

RecordedTick decode_tick(const unsigned char* in, std::uint32_t version) {
    Decoder d(in);
    RecordedTick t;
    t.t_s = d.f64();
    t.device.t_s = d.f64();
    t.device.pose.position = d.vec();
    t.device.pose.orientation.w = d.f64();
    t.device.pose.orientation.x = d.f64();
    t.device.pose.orientation.y = d.f64();
    t.device.pose.orientation.z = d.f64();
    t.device.velocity_m_s = d.vec();
    t.device.buttons = d.u32();
    t.wand_centre_m = d.vec();
    t.rotation_axis = d.vec();
    t.rotation_angle_rad = d.f64();
    t.top_m = d.vec();
    t.bottom_m = d.vec();
    t.top_contact_m = d.vec();
    t.bottom_contact_m = d.vec();
    t.top_deviation_m = d.f64();
    t.bottom_deviation_m = d.f64();
    t.top_force_n = d.vec();
    t.bottom_force_n = d.vec();
    t.force_n = d.vec();
    t.torque_nm = d.vec();
    t.top_collision_id = d.i32();
    t.bottom_collision_id = d.i32();
    t.buttons = d.u32();
    t.tool_mode = d.u8();
    t.valid = d.u8();
    if (version < 2) {
        t.op = t.tool_mode;
        return t;
    }
    t.op = d.u8();
    t.material = d.u8();
    t.tool.kind = static_cast<ToolKind>(d.u8());
    t.tool.radius_m = d.f64();
    t.tool.length_m = d.f64();
    if (version >= 3) t.symmetry = symmetry_from_bits(d.u32());
    if (version >= 4) t.workpiece = d.u8();
    return t;
}

// ---- messages ----
std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}
std::string vec_str(const Vec3& v) { return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ")"; }

std::string check_finite(const char* field, double v) {
    return std::isfinite(v) ? std::string() : std::string(field) + " = " + num(v) + " is not finite";
}
std::string check_finite(const char* field, const Vec3& v) {
    return is_finite(v) ? std::string() : std::string(field) + " = " + vec_str(v) + " is not finite";
}

bool recorded_mark_kind(const std::string& k) {
    return k == "undo" || k == "redo" || k == "end_stroke" || k == "finer" || k == "coarser";
}

std::string header_json(const std::string& path, const RecordingHeader& h) {
    if (!std::isfinite(h.period_s) || h.period_s <= 0.0)
        throw Error(path + ": header.period_s = " + num(h.period_s) + " must be finite and > 0");
    nlohmann::json j = {{"device_name", h.device_name},
                        {"period_s", h.period_s},
                        {"workspace_mode", h.workspace_mode},
                        {"notes", h.notes}};
    if (h.marks) {
        nlohmann::json marks = nlohmann::json::array();
        for (std::size_t k = 0; k < h.marks->size(); ++k) {
            const RecordedMark& m = (*h.marks)[k];
            if (!recorded_mark_kind(m.kind))
                throw Error(path + ": header.marks[" + std::to_string(k) + "].kind = \"" + m.kind +
                            "\" is not undo, redo, end_stroke, finer or coarser");
            if (k > 0 && m.after_samples < (*h.marks)[k - 1].after_samples)
                throw Error(path + ": header.marks[" + std::to_string(k) + "].after_samples decreases");
            if (m.workpiece >= kMaxRecordedWorkpieces)
                throw Error(path + ": header.marks[" + std::to_string(k) + "].workpiece = " + std::to_string(m.workpiece) +
                            " is not 0.." + std::to_string(kMaxRecordedWorkpieces - 1));
            nlohmann::json e = {{"after_samples", m.after_samples}, {"kind", m.kind}};
            if (m.workpiece > 0) e["workpiece"] = m.workpiece;  // absent for the first, as before
            marks.push_back(std::move(e));
        }
        j["marks"] = std::move(marks);
    }
    if (!h.poses.empty()) j["poses"] = recorded_poses_json(path, h.poses);
    if (!h.menu.empty()) {  // the app's menu track, kept as it gave it (an array)
        nlohmann::json menu;
        try {
            menu = nlohmann::json::parse(h.menu);
        } catch (const nlohmann::json::exception&) {
            throw Error(path + ": header.menu is not JSON");
        }
        if (!menu.is_array()) throw Error(path + ": header.menu is not a JSON array");
        j["menu"] = std::move(menu);
    }
    try {
        return j.dump();
    } catch (const nlohmann::json::exception& e) {
        throw Error(path + ": header has a string that is not valid UTF-8 (" + e.what() + ")");
    }
}

RecordingHeader parse_header(const std::string& path, const std::string& text) {
    const std::string where = path + ": header text (byte " + std::to_string(kRecordingPreambleBytes) + ")";
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        // The parser's reason without its "[json.exception...] " tag; it quotes the bytes it last read.
        const std::string what = e.what();
        const std::size_t tag = what.find("] ");
        throw Error(where + " is not JSON: " + printable(tag == std::string::npos ? what : what.substr(tag + 2), 200));
    }
    if (!j.is_object()) throw Error(where + " is not a JSON object");
    auto string_field = [&](const char* key) {
        const auto it = j.find(key);
        if (it == j.end() || !it->is_string()) throw Error(where + ": \"" + key + "\" missing or not a string");
        return it->get<std::string>();
    };
    RecordingHeader h;
    h.device_name = string_field("device_name");
    h.workspace_mode = string_field("workspace_mode");
    h.notes = string_field("notes");
    const auto it = j.find("period_s");
    if (it == j.end() || !it->is_number()) throw Error(where + ": \"period_s\" missing or not a number");
    h.period_s = it->get<double>();
    if (!std::isfinite(h.period_s) || h.period_s <= 0.0)
        throw Error(where + ": period_s = " + num(h.period_s) + " must be finite and > 0");
    if (const auto m = j.find("marks"); m != j.end()) {
        if (!m->is_array()) throw Error(where + ": \"marks\" is not an array");
        h.marks.emplace();
        for (std::size_t k = 0; k < m->size(); ++k) {
            const nlohmann::json& e = (*m)[k];
            const std::string at = where + ": marks[" + std::to_string(k) + "]";
            if (!e.is_object()) throw Error(at + " is not an object");
            const auto n = e.find("after_samples"), kind = e.find("kind");
            if (n == e.end() || !n->is_number_unsigned())
                throw Error(at + ".after_samples missing or not an integer >= 0");
            if (kind == e.end() || !kind->is_string() || !recorded_mark_kind(kind->get<std::string>()))
                throw Error(at + ".kind missing or not \"undo\", \"redo\", \"end_stroke\", \"finer\" or \"coarser\"");
            RecordedMark r{n->get<std::uint64_t>(), kind->get<std::string>()};
            if (const auto w = e.find("workpiece"); w != e.end()) {
                if (!w->is_number_unsigned() || w->get<std::uint64_t>() >= static_cast<std::uint64_t>(kMaxRecordedWorkpieces))
                    throw Error(at + ".workpiece is not an integer 0.." + std::to_string(kMaxRecordedWorkpieces - 1));
                r.workpiece = static_cast<std::uint8_t>(w->get<std::uint64_t>());
            }
            if (!h.marks->empty() && r.after_samples < h.marks->back().after_samples)
                throw Error(at + ".after_samples = " + std::to_string(r.after_samples) + " is less than the mark before it (" +
                            std::to_string(h.marks->back().after_samples) + ")");
            h.marks->push_back(std::move(r));
        }
    }
    if (const auto p = j.find("poses"); p != j.end()) h.poses = parse_recorded_poses(where, *p);
    if (const auto m = j.find("menu"); m != j.end()) {
        if (!m->is_array()) throw Error(where + ": \"menu\" is not an array");
        h.menu = m->dump();  // checked entry by entry by the app that reads it (app/menu/menu_frame.hpp)
    }
    return h;
}

}  // namespace

void to_axis_angle(const Quat& q_in, Vec3& axis_out, double& angle_rad_out) {
    axis_out = Vec3(1.0, 0.0, 0.0);
    const double n = std::sqrt(q_in.w * q_in.w + q_in.x * q_in.x + q_in.y * q_in.y + q_in.z * q_in.z);
    if (!std::isfinite(n) || n == 0.0) {
        angle_rad_out = std::numeric_limits<double>::quiet_NaN();
        return;
    }
    // q and -q are the same rotation; w >= 0 keeps the angle in [0, pi].
    const double s = q_in.w < 0.0 ? -1.0 / n : 1.0 / n;
    const double w = q_in.w * s;
    const Vec3 v(q_in.x * s, q_in.y * s, q_in.z * s);
    const double vn = glm::length(v);
    const double angle = 2.0 * std::atan2(vn, w);  // better conditioned than 2*acos(w) near 0
    if (!(angle >= 1e-12)) {
        angle_rad_out = 0.0;
        return;
    }
    axis_out = v / vn;
    angle_rad_out = angle;
}

std::string check_tick(const RecordedTick& t, double previous_t_s) {
    if (!std::isfinite(t.t_s)) return "t_s = " + num(t.t_s) + " is not finite";
    if (std::isfinite(previous_t_s) && !(t.t_s > previous_t_s))
        return "t_s = " + num(t.t_s) + " does not increase (previous tick: " + num(previous_t_s) + ")";
    if (t.valid > 1) return "valid = " + std::to_string(t.valid) + " is not 0 or 1";
    constexpr unsigned most = static_cast<unsigned>(ToolOp::kPlace);
    if (t.tool_mode > most) return "tool_mode = " + std::to_string(t.tool_mode) + " is not a ToolOp value (0..8)";
    if (t.op > most) return "op = " + std::to_string(t.op) + " is not a ToolOp value (0..8)";
    if (static_cast<unsigned>(t.tool.kind) > 2)
        return "tool.kind = " + std::to_string(static_cast<unsigned>(t.tool.kind)) + " is not a ToolKind value (0..2)";
    if (t.material > kMaxMaterialId)
        return "material = " + std::to_string(t.material) + " is not a material id (0.." +
               std::to_string(kMaxMaterialId) + ")";
    if (!valid_symmetry(t.symmetry))
        return "symmetry = {mirrors " + std::to_string(t.symmetry.mirrors) + ", radial axis " +
               std::to_string(t.symmetry.radial_axis) + ", radial copies " + std::to_string(t.symmetry.radial_copies) +
               "} is not a valid symmetry (mirrors 0..7 without radial copies, or 2..32 copies about axis 0..2)";
    if (t.workpiece < -1 || t.workpiece >= kMaxRecordedWorkpieces)
        return "workpiece = " + std::to_string(t.workpiece) + " is not a workpiece index (0.." +
               std::to_string(kMaxRecordedWorkpieces - 1) + ")";
    if (!(std::isfinite(t.tool.radius_m) && t.tool.radius_m >= 0.0))
        return "tool.radius_m = " + num(t.tool.radius_m) + " must be finite and >= 0";
    if (!(std::isfinite(t.tool.length_m) && t.tool.length_m >= 0.0))
        return "tool.length_m = " + num(t.tool.length_m) + " must be finite and >= 0";
    std::string e;
    if (t.valid == 1) {
        const Quat& q = t.device.pose.orientation;
        if (!(e = check_finite("device.t_s", t.device.t_s)).empty()) return e;
        if (!(e = check_finite("device.pose.position", t.device.pose.position)).empty()) return e;
        if (!std::isfinite(q.w) || !std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
            return "device.pose.orientation = (" + num(q.w) + ", " + num(q.x) + ", " + num(q.y) + ", " + num(q.z) +
                   ") is not finite although valid = 1";
        if (!(e = check_finite("device.velocity_m_s", t.device.velocity_m_s)).empty()) return e;
    }
    const std::pair<const char*, const Vec3*> vecs[] = {
        {"wand_centre_m", &t.wand_centre_m}, {"rotation_axis", &t.rotation_axis},
        {"top_m", &t.top_m},                 {"bottom_m", &t.bottom_m},
        {"top_contact_m", &t.top_contact_m}, {"bottom_contact_m", &t.bottom_contact_m},
        {"top_force_n", &t.top_force_n},     {"bottom_force_n", &t.bottom_force_n},
        {"force_n", &t.force_n},             {"torque_nm", &t.torque_nm}};
    for (const auto& [name, v] : vecs)
        if (!(e = check_finite(name, *v)).empty()) return e;
    if (std::abs(glm::length(t.rotation_axis) - 1.0) > 1e-6)
        return "rotation_axis = " + vec_str(t.rotation_axis) + " is not unit length";
    if (!(t.rotation_angle_rad >= 0.0 && t.rotation_angle_rad <= kTwoPi))
        return "rotation_angle_rad = " + num(t.rotation_angle_rad) + " is not in [0, 2*pi]";
    if (!(t.top_deviation_m >= 0.0) || !std::isfinite(t.top_deviation_m))
        return "top_deviation_m = " + num(t.top_deviation_m) + " must be finite and >= 0";
    if (!(t.bottom_deviation_m >= 0.0) || !std::isfinite(t.bottom_deviation_m))
        return "bottom_deviation_m = " + num(t.bottom_deviation_m) + " must be finite and >= 0";
    if (t.top_collision_id < -1) return "top_collision_id = " + std::to_string(t.top_collision_id) + " is below -1";
    if (t.bottom_collision_id < -1)
        return "bottom_collision_id = " + std::to_string(t.bottom_collision_id) + " is below -1";
    return {};
}

// ---- writer ----

RecordingWriter::RecordingWriter(const std::string& path, const RecordingHeader& header)
    : path_(path), last_t_s_(std::numeric_limits<double>::quiet_NaN()), uncaught_at_open_(std::uncaught_exceptions()) {
    const std::string text = header_json(path, header);
    if (text.size() > std::numeric_limits<std::uint32_t>::max()) throw Error(path + ": header text too long");
    atomic_.emplace(path);  // throws "<path>: cannot create ..." when the folder cannot hold it
    unsigned char pre[kRecordingPreambleBytes];
    std::memcpy(pre, kRecordingMagic, 8);
    Encoder e(pre + 8);
    e.u32(kRecordingVersion);
    e.u32(static_cast<std::uint32_t>(kRecordedTickBytes));
    e.u64(kOpenCount);
    e.u32(0);  // checksum, filled by close()
    e.u32(static_cast<std::uint32_t>(text.size()));
    std::FILE* file = atomic_->stream();
    const bool ok = std::fwrite(pre, 1, sizeof pre, file) == sizeof pre &&
                    std::fwrite(text.data(), 1, text.size(), file) == text.size();
    if (!ok) {
        const int err = errno;
        atomic_.reset();  // discards the temporary file
        throw Error(path + ": cannot write the header: " + std::strerror(err));
    }
    crc_ = crc32_ieee(text.data(), text.size());
}

RecordingWriter::~RecordingWriter() {
    if (!atomic_) return;
    if (std::uncaught_exceptions() > uncaught_at_open_) {
        atomic_.reset();  // unwinding: discard the temporary file, so nobody mistakes it for a whole session
        return;
    }
    try {
        close();
    } catch (const Error&) {
        // a destructor cannot report; close() explicitly to see the error
    }
}

void RecordingWriter::write(const RecordedTick& tick) {
    if (!atomic_) throw Error(path_ + ": write after close");
    const std::string problem = check_tick(tick, last_t_s_);
    if (!problem.empty()) throw Error(path_ + ": tick " + std::to_string(count_) + ": " + problem);
    unsigned char rec[kRecordedTickBytes];
    encode_tick(tick, rec);
    if (std::fwrite(rec, 1, sizeof rec, atomic_->stream()) != sizeof rec)
        throw Error(path_ + ": tick " + std::to_string(count_) + ": write failed: " + std::strerror(errno));
    crc_ = crc32_ieee(rec, sizeof rec, crc_);
    last_t_s_ = tick.t_s;
    ++count_;
}

void RecordingWriter::close() {
    if (!atomic_) return;
    std::FILE* f = atomic_->stream();
    unsigned char tail[12];
    Encoder e(tail);
    e.u64(static_cast<std::uint64_t>(count_));
    e.u32(crc_);
    const bool ok = std::fflush(f) == 0 && std::fseek(f, 16, SEEK_SET) == 0 && std::fwrite(tail, 1, sizeof tail, f) == sizeof tail;
    const int err = errno;
    if (!ok) {
        atomic_.reset();
        throw Error(path_ + ": cannot finish the file: " + std::strerror(err ? err : EIO));
    }
    AtomicFile file = std::move(*atomic_);
    atomic_.reset();
    file.commit();  // throws "<path>: cannot write ..." (the temporary file removed, path as it was)
}

void write_recording(const std::string& path, const Recording& recording) {
    RecordingWriter w(path, recording.header);
    for (const RecordedTick& t : recording.ticks) w.write(t);
    w.close();
}

// ---- reader ----

Recording read_recording(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open: " + std::strerror(errno));
    in.seekg(0, std::ios::end);
    const std::streamoff file_size = in.tellg();
    in.seekg(0, std::ios::beg);
    if (file_size < 0) throw Error(path + ": cannot read its size");
    const auto size = static_cast<std::uint64_t>(file_size);
    auto read_exact = [&](void* dst, std::size_t n, std::uint64_t at) {
        if (!in.read(static_cast<char*>(dst), static_cast<std::streamsize>(n)))
            throw Error(path + ": read error at byte " + std::to_string(at));
    };

    unsigned char pre[kRecordingPreambleBytes];
    const std::size_t head = size < sizeof pre ? static_cast<std::size_t>(size) : sizeof pre;
    read_exact(pre, head, 0);
    if (head >= 8 && std::memcmp(pre, kRecordingMagic, 8) != 0)
        throw Error(path + ": not a tridex recording (byte 0: magic is not \"TRDXREC\")");
    if (head < sizeof pre)
        throw Error(path + ": truncated: " + std::to_string(size) + " bytes, shorter than the " +
                    std::to_string(sizeof pre) + "-byte preamble");
    Decoder d(pre + 8);
    const std::uint32_t version = d.u32();
    const std::uint32_t tick_bytes = d.u32();
    const std::uint64_t count = d.u64();
    const std::uint32_t stored_crc = d.u32();
    const std::uint32_t header_len = d.u32();
    if (version < 1 || version > kRecordingVersion)
        throw Error(path + ": byte 8: unsupported version " + std::to_string(version) + " (this build reads versions 1 to " +
                    std::to_string(kRecordingVersion) + ")");
    const std::size_t tick_size = version == 1   ? kRecordedTickBytesV1
                                  : version == 2 ? kRecordedTickBytesV2
                                  : version == 3 ? kRecordedTickBytesV3
                                                 : kRecordedTickBytes;
    if (tick_bytes != tick_size)
        throw Error(path + ": byte 12: tick record size " + std::to_string(tick_bytes) + ", expected " +
                    std::to_string(tick_size) + " for version " + std::to_string(version));
    if (count == kOpenCount)
        throw Error(path + ": byte 16: unfinished recording (the writer was never closed)");
    const std::uint64_t ticks_at = kRecordingPreambleBytes + std::uint64_t{header_len};
    if (ticks_at > size)
        throw Error(path + ": truncated: the " + std::to_string(header_len) + "-byte header text at byte 32 runs past the end (" +
                    std::to_string(size) + " bytes)");

    std::string text(header_len, '\0');
    read_exact(text.data(), text.size(), kRecordingPreambleBytes);
    std::uint32_t crc = crc32_ieee(text.data(), text.size());
    Recording rec;
    rec.header = parse_header(path, text);

    const std::uint64_t body = size - ticks_at;
    const std::uint64_t whole = body / tick_size;
    if (count > whole)
        throw Error(path + ": truncated: the preamble says " + std::to_string(count) + " ticks but the file holds " +
                    std::to_string(whole) + " whole ticks; tick " + std::to_string(whole) + " is cut at byte " +
                    std::to_string(size));
    if (body != count * tick_size)
        throw Error(path + ": " + std::to_string(body - count * tick_size) + " trailing byte(s) after tick " +
                    std::to_string(count) + " at byte " + std::to_string(ticks_at + count * tick_size));

    rec.ticks.reserve(static_cast<std::size_t>(count));
    constexpr std::size_t kChunk = 1024;
    std::vector<unsigned char> buf(kChunk * tick_size);
    double previous = std::numeric_limits<double>::quiet_NaN();
    for (std::uint64_t first = 0; first < count; first += kChunk) {
        const std::size_t n = static_cast<std::size_t>(count - first < kChunk ? count - first : kChunk);
        read_exact(buf.data(), n * tick_size, ticks_at + first * tick_size);
        crc = crc32_ieee(buf.data(), n * tick_size, crc);
        for (std::size_t k = 0; k < n; ++k) {
            const RecordedTick t = decode_tick(buf.data() + k * tick_size, version);
            const std::string problem = check_tick(t, previous);
            if (!problem.empty())
                throw Error(path + ": tick " + std::to_string(first + k) + " (byte " +
                            std::to_string(ticks_at + (first + k) * tick_size) + "): " + problem);
            previous = t.t_s;
            rec.ticks.push_back(t);
        }
    }
    if (crc != stored_crc) {
        char msg[96];
        std::snprintf(msg, sizeof msg, ": checksum mismatch (stored 0x%08X, computed 0x%08X): the file is corrupted",
                      stored_crc, crc);
        throw Error(path + msg);
    }
    return rec;
}

// ---- CSV ----

const std::vector<std::string>& recording_csv_columns() {
    static const std::vector<std::string> columns = [] {
        std::vector<std::string> c = {"t_s",       "device_t_s", "device_x_m",    "device_y_m",    "device_z_m",
                                      "device_qw", "device_qx",  "device_qy",     "device_qz",     "device_vx_m_s",
                                      "device_vy_m_s", "device_vz_m_s", "device_buttons"};
        auto xyz = [&c](const std::string& stem, const std::string& unit) {
            for (const char* a : {"x", "y", "z"}) c.push_back(stem + "_" + a + unit);
        };
        xyz("wand_centre", "_m");
        xyz("rotation_axis", "");
        c.push_back("rotation_angle_rad");
        xyz("top", "_m");
        xyz("bottom", "_m");
        xyz("top_collision", "_m");
        xyz("bottom_collision", "_m");
        c.push_back("top_deviation_m");
        c.push_back("bottom_deviation_m");
        xyz("top_force", "_n");
        xyz("bottom_force", "_n");
        xyz("force", "_n");
        xyz("torque", "_nm");
        for (const char* s : {"top_collision_id", "bottom_collision_id", "buttons", "tool_mode", "valid", "op", "material",
                              "tool_kind", "tool_radius_m", "tool_length_m"})
            c.push_back(s);
        return c;
    }();
    return columns;
}

namespace {

void put_num(std::string& row, double v) {
    row += ',';
    if (std::isnan(v)) {
        row += "nan";
    } else if (std::isinf(v)) {
        row += v > 0 ? "inf" : "-inf";
    } else {
        row += num(v);
    }
}
void put_vec(std::string& row, const Vec3& v) { put_num(row, v.x), put_num(row, v.y), put_num(row, v.z); }
void put_int(std::string& row, long long v) { row += ',' + std::to_string(v); }

}  // namespace

void write_recording_csv(const std::string& path, const Recording& recording) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw Error(path + ": cannot create: " + std::strerror(errno));
    std::string line;
    for (const std::string& c : recording_csv_columns()) line += (line.empty() ? "" : ",") + c;
    line += '\n';
    bool ok = std::fputs(line.c_str(), f) >= 0;
    for (std::size_t i = 0; ok && i < recording.ticks.size(); ++i) {
        const RecordedTick& t = recording.ticks[i];
        const Quat& q = t.device.pose.orientation;
        line.clear();
        put_num(line, t.t_s);
        put_num(line, t.device.t_s);
        put_vec(line, t.device.pose.position);
        put_num(line, q.w), put_num(line, q.x), put_num(line, q.y), put_num(line, q.z);
        put_vec(line, t.device.velocity_m_s);
        put_int(line, t.device.buttons);
        put_vec(line, t.wand_centre_m);
        put_vec(line, t.rotation_axis);
        put_num(line, t.rotation_angle_rad);
        put_vec(line, t.top_m), put_vec(line, t.bottom_m);
        put_vec(line, t.top_contact_m), put_vec(line, t.bottom_contact_m);
        put_num(line, t.top_deviation_m), put_num(line, t.bottom_deviation_m);
        put_vec(line, t.top_force_n), put_vec(line, t.bottom_force_n), put_vec(line, t.force_n);
        put_vec(line, t.torque_nm);
        put_int(line, t.top_collision_id), put_int(line, t.bottom_collision_id);
        put_int(line, t.buttons), put_int(line, t.tool_mode), put_int(line, t.valid);
        put_int(line, t.op), put_int(line, t.material), put_int(line, static_cast<int>(t.tool.kind));
        put_num(line, t.tool.radius_m), put_num(line, t.tool.length_m);
        line += '\n';
        ok = std::fputs(line.c_str() + 1, f) >= 0;  // every field wrote a leading comma: skip the first
    }
    const int err = errno;
    ok = (std::fclose(f) == 0) && ok;
    if (!ok) throw Error(path + ": cannot write: " + std::strerror(err ? err : errno));
}

}  // namespace tridex::devices
