// devices/tracking/dtrack_parser.cpp - strict parser of DTrack ASCII datagrams.
#include "devices/tracking/dtrack_parser.hpp"

#include <charconv>
#include <cmath>

namespace tridex::devices {
namespace {

constexpr double kMmToM = 1e-3;
constexpr double kMaxCoordinateMm = 1e6;     // 1 km: anything farther is not a tracked room
constexpr double kRotationTolerance = 1e-3;  // DTrack prints 6 decimals

/// A cursor over one line's fields. Every read returns kNone or the fault found.
class Fields {
public:
    explicit Fields(std::string_view s) : s_(s) {}

    void skip_space() {
        while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t')) ++i_;
    }
    bool at_end() {
        skip_space();
        return i_ >= s_.size();
    }
    /// The next token (up to a space, a bracket or the end), or empty at the end / before a bracket.
    std::string_view token() {
        skip_space();
        const std::size_t b = i_;
        while (i_ < s_.size() && s_[i_] != ' ' && s_[i_] != '\t' && s_[i_] != '[' && s_[i_] != ']') ++i_;
        return s_.substr(b, i_ - b);
    }
    DTrackReject number(double& v) {
        const std::string_view t = token();
        if (t.empty()) return missing();
        const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc() || p != t.data() + t.size()) return DTrackReject::kNotNumeric;
        return std::isfinite(v) ? DTrackReject::kNone : DTrackReject::kNotFinite;
    }
    DTrackReject integer(long long& v) {
        const std::string_view t = token();
        if (t.empty()) return missing();
        const auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec == std::errc::result_out_of_range) return DTrackReject::kOutOfRange;
        if (ec != std::errc() || p != t.data() + t.size()) return DTrackReject::kNotNumeric;
        return DTrackReject::kNone;
    }
    /// Expects `c` ('[' or ']') next.
    DTrackReject expect(char c) {
        skip_space();
        if (i_ >= s_.size()) return DTrackReject::kTruncated;
        if (s_[i_] != c) return DTrackReject::kSyntax;
        ++i_;
        return DTrackReject::kNone;
    }
    /// True when the next non-space character is ']'.
    bool closing() {
        skip_space();
        return i_ < s_.size() && s_[i_] == ']';
    }
    /// True when the next non-space character is '['.
    bool opening() {
        skip_space();
        return i_ < s_.size() && s_[i_] == '[';
    }

private:
    DTrackReject missing() {
        if (i_ >= s_.size()) return DTrackReject::kTruncated;
        return DTrackReject::kSyntax;  // a bracket where a value belongs
    }
    std::string_view s_;
    std::size_t i_ = 0;
};

#define TRIDEX_TRY(expr)                                                          \
    do {                                                                          \
        if (const DTrackReject r_ = (expr); r_ != DTrackReject::kNone) return r_; \
    } while (false)

/// Reads a bracketed block of exactly `n` numbers, or (when n_alt > 0) of n_alt numbers.
DTrackReject number_block(Fields& f, double* v, int n, int n_alt = 0, int* got = nullptr) {
    TRIDEX_TRY(f.expect('['));
    int k = 0;
    const int cap = n_alt > n ? n_alt : n;
    while (!f.closing()) {
        if (f.at_end()) return DTrackReject::kTruncated;
        if (k == cap) return DTrackReject::kSyntax;
        TRIDEX_TRY(f.number(v[k]));
        ++k;
    }
    if (k != n && k != n_alt) return k < n ? DTrackReject::kTruncated : DTrackReject::kSyntax;
    if (got) *got = k;
    return f.expect(']');
}

DTrackReject check_quality(double q) {
    return (q == -1.0 || (q >= 0.0 && q <= 1.0)) ? DTrackReject::kNone : DTrackReject::kOutOfRange;
}

DTrackReject check_id(long long id) {
    return (id >= 0 && id <= kDTrackMaxId) ? DTrackReject::kNone : DTrackReject::kOutOfRange;
}

/// Reads the location (mm) and rotation blocks into `b`; checks them when the body is tracked.
DTrackReject pose_blocks(Fields& f, DTrackBody& b, bool allow_angles) {
    double loc[6];
    TRIDEX_TRY(number_block(f, loc, 3, allow_angles ? 6 : 0));
    double r[9];
    TRIDEX_TRY(number_block(f, r, 9));
    for (int k = 0; k < 3; ++k)
        if (std::abs(loc[k]) > kMaxCoordinateMm) return DTrackReject::kOutOfRange;
    b.position_m = Vec3(loc[0], loc[1], loc[2]) * kMmToM;
    for (int c = 0; c < 3; ++c)
        for (int row = 0; row < 3; ++row) b.rotation[c][row] = r[3 * c + row];  // b0..b8 column by column
    if (b.tracked()) {
        const glm::dmat3 e = glm::transpose(b.rotation) * b.rotation;
        for (int c = 0; c < 3; ++c)
            for (int row = 0; row < 3; ++row)
                if (std::abs(e[c][row] - (c == row ? 1.0 : 0.0)) > kRotationTolerance)
                    return DTrackReject::kNotRotation;
        if (glm::determinant(b.rotation) < 0.0) return DTrackReject::kNotRotation;
    }
    return DTrackReject::kNone;
}

/// A body count: a whole number in 0..kDTrackMaxId + 1.
DTrackReject count(Fields& f, int& n) {
    long long v = 0;
    TRIDEX_TRY(f.integer(v));
    if (v < 0 || v > kDTrackMaxId + 1) return DTrackReject::kBodyCount;
    n = static_cast<int>(v);
    return DTrackReject::kNone;
}

/// Most extra values an id block may carry after the ones tridex reads.
constexpr int kMaxExtraValues = 16;

/// The rest of an id block after the values tridex reads: finite numbers a later DTrack may add (ART's SDK ignores
/// additional data inside a block), counted in out.extra_values, then ']'.
DTrackReject extra_block_values(Fields& f, DTrackFrame& out) {
    for (int k = 0; !f.closing(); ++k) {
        if (f.at_end()) return DTrackReject::kTruncated;
        if (k == kMaxExtraValues || f.opening()) return DTrackReject::kSyntax;
        double v = 0.0;
        TRIDEX_TRY(f.number(v));
        ++out.extra_values;
    }
    return f.expect(']');
}

/// After the declared blocks: nothing, or the line carries more blocks than it declared.
DTrackReject line_end(Fields& f) {
    if (f.at_end()) return DTrackReject::kNone;
    return f.opening() ? DTrackReject::kBodyCount : DTrackReject::kSyntax;
}

/// Before each declared block: a line that ends cleanly here has fewer bodies than it declared.
DTrackReject body_start(Fields& f) { return f.at_end() ? DTrackReject::kBodyCount : DTrackReject::kNone; }

DTrackReject parse_6d(Fields& f, DTrackFrame& out) {
    int n = 0;
    TRIDEX_TRY(count(f, n));
    for (int i = 0; i < n; ++i) {
        TRIDEX_TRY(body_start(f));
        DTrackBody b;
        TRIDEX_TRY(f.expect('['));
        long long id = 0;
        TRIDEX_TRY(f.integer(id));
        TRIDEX_TRY(check_id(id));
        TRIDEX_TRY(f.number(b.quality));
        TRIDEX_TRY(check_quality(b.quality));
        TRIDEX_TRY(extra_block_values(f, out));
        b.id = static_cast<int>(id);
        TRIDEX_TRY(pose_blocks(f, b, true));
        if (out.body(b.id)) return DTrackReject::kDuplicate;
        out.bodies.push_back(b);
    }
    return line_end(f);
}

DTrackReject parse_6df2(Fields& f, DTrackFrame& out) {
    int defined = 0, n = 0;
    TRIDEX_TRY(count(f, defined));
    TRIDEX_TRY(count(f, n));
    if (n > defined) return DTrackReject::kBodyCount;
    out.flysticks_defined = defined;
    for (int i = 0; i < n; ++i) {
        TRIDEX_TRY(body_start(f));
        DTrackFlystick fs;
        TRIDEX_TRY(f.expect('['));
        long long id = 0, nbt = 0, nct = 0;
        TRIDEX_TRY(f.integer(id));
        TRIDEX_TRY(check_id(id));
        if (id >= defined) return DTrackReject::kOutOfRange;
        TRIDEX_TRY(f.number(fs.body.quality));
        TRIDEX_TRY(check_quality(fs.body.quality));
        TRIDEX_TRY(f.integer(nbt));
        TRIDEX_TRY(f.integer(nct));
        if (nbt < 0 || nbt > kDTrackMaxButtons || nct < 0 || nct > kDTrackMaxControllers)
            return DTrackReject::kOutOfRange;
        TRIDEX_TRY(extra_block_values(f, out));
        fs.body.id = static_cast<int>(id);
        fs.button_count = static_cast<int>(nbt);
        fs.controller_count = static_cast<int>(nct);
        TRIDEX_TRY(pose_blocks(f, fs.body, false));
        // Buttons: ceil(nbt / 32) bit fields of 32 buttons each, then nct controller values.
        TRIDEX_TRY(f.expect('['));
        const int words = (fs.button_count + 31) / 32;
        for (int w = 0; w < words; ++w) {
            long long bits = 0;
            TRIDEX_TRY(f.integer(bits));
            if (bits < 0 || bits > 0xFFFFFFFFLL) return DTrackReject::kOutOfRange;
            fs.buttons |= static_cast<std::uint64_t>(bits) << (32 * w);
        }
        if (fs.button_count < 64 && (fs.buttons >> fs.button_count) != 0) return DTrackReject::kOutOfRange;
        for (int c = 0; c < fs.controller_count; ++c) {
            TRIDEX_TRY(f.number(fs.controllers[c]));
            if (std::abs(fs.controllers[c]) > 1.0) return DTrackReject::kOutOfRange;
        }
        if (!f.closing()) return f.at_end() ? DTrackReject::kTruncated : DTrackReject::kSyntax;
        TRIDEX_TRY(f.expect(']'));
        for (const DTrackFlystick& o : out.flysticks)
            if (o.body.id == fs.body.id) return DTrackReject::kDuplicate;
        out.flysticks.push_back(fs);
    }
    return line_end(f);
}

/// Line types this parser reads; a second line of the same type is a duplicate.
enum LineType { kFr, kTs, kTs2, k6dcal, k6d, k6df2, kLineTypes };

/// A DTrack line identifier: lower-case letters and digits ("fr", "6df2", "ts2"); anything else is not DTrack output.
bool dtrack_identifier(std::string_view id) {
    if (id.empty() || id.size() > 16) return false;
    for (const char c : id)
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'))) return false;
    return true;
}

/// `ts2 <s> <us> <latency us>` (DTRACK3's extended timestamp, as ART's DTrackSDK reads it): seconds since 1970
/// (reduced to the time of day, as `ts`), microseconds, and the tracker's latency in microseconds.
DTrackReject parse_ts2(Fields& f, DTrackFrame& out) {
    long long sec = 0, usec = 0, latency = 0;
    TRIDEX_TRY(f.integer(sec));
    TRIDEX_TRY(f.integer(usec));
    TRIDEX_TRY(f.integer(latency));
    if (sec < 0 || usec < 0 || usec >= 1000000 || latency < 0 || latency > 10000000) return DTrackReject::kOutOfRange;
    out.has_timestamp = true;
    out.timestamp_s = static_cast<double>(sec % 86400) + static_cast<double>(usec) * 1e-6;
    out.has_latency = true;
    out.latency_s = static_cast<double>(latency) * 1e-6;
    return DTrackReject::kNone;
}

/// DTrack line types that are valid but not used here.
bool ignored_type(std::string_view id) {
    static constexpr std::string_view kIgnored[] = {"3d",    "6dcov", "6df", "6di",   "6dj", "6dmt",
                                                    "6dmt2", "6dmtr", "gl",  "glcal", "st"};
    for (const std::string_view k : kIgnored)
        if (id == k) return true;
    return false;
}

DTrackReject parse_line(std::string_view line, DTrackFrame& out, bool (&seen)[kLineTypes]) {
    Fields f(line);
    const std::string_view id = f.token();
    LineType type = kLineTypes;
    if (id == "fr")
        type = kFr;
    else if (id == "ts")
        type = kTs;
    else if (id == "ts2")
        type = kTs2;
    else if (id == "6dcal")
        type = k6dcal;
    else if (id == "6d")
        type = k6d;
    else if (id == "6df2")
        type = k6df2;
    else if (ignored_type(id) || dtrack_identifier(id)) {
        // Every DTrack line carries values after its identifier: a bare known one is a datagram cut short, a bare
        // unknown one is not DTrack output (or a datagram cut inside an identifier).
        if (f.at_end()) return ignored_type(id) ? DTrackReject::kTruncated : DTrackReject::kUnknownLine;
        // Types tridex does not read, and those of a later DTrack, are skipped as ART's SDK does.
        ++(ignored_type(id) ? out.ignored_lines : out.unknown_lines);
        return DTrackReject::kNone;
    } else {
        return DTrackReject::kUnknownLine;
    }
    if (seen[type]) return DTrackReject::kDuplicate;
    seen[type] = true;
    switch (type) {
        case kFr: {
            long long v = 0;
            TRIDEX_TRY(f.integer(v));
            if (v < 0 || v > 0xFFFFFFFFLL) return DTrackReject::kOutOfRange;
            out.has_frame_counter = true;
            out.frame_counter = static_cast<std::uint32_t>(v);
            break;
        }
        case kTs: {
            double ts = 0.0;
            TRIDEX_TRY(f.number(ts));
            if (ts < 0.0) return DTrackReject::kOutOfRange;
            if (!seen[kTs2]) out.timestamp_s = ts;  // a datagram with both: ts2's time, whatever the line order
            out.has_timestamp = true;
            break;
        }
        case kTs2: {
            TRIDEX_TRY(parse_ts2(f, out));
            break;
        }
        case k6dcal: {
            int n = 0;
            TRIDEX_TRY(count(f, n));
            out.calibrated_bodies = n;
            break;
        }
        case k6d: return parse_6d(f, out);
        case k6df2: return parse_6df2(f, out);
        case kLineTypes: break;
    }
    return f.at_end() ? DTrackReject::kNone : DTrackReject::kSyntax;
}

bool text_byte(unsigned char c) { return (c >= 0x20 && c <= 0x7E) || c == '\t' || c == '\r' || c == '\n'; }

}  // namespace

const char* to_string(DTrackReject r) {
    switch (r) {
        case DTrackReject::kNone: return "none";
        case DTrackReject::kEmpty: return "empty";
        case DTrackReject::kTooLarge: return "too_large";
        case DTrackReject::kNotText: return "not_text";
        case DTrackReject::kUnknownLine: return "unknown_line";
        case DTrackReject::kTruncated: return "truncated";
        case DTrackReject::kNotNumeric: return "not_numeric";
        case DTrackReject::kNotFinite: return "not_finite";
        case DTrackReject::kSyntax: return "syntax";
        case DTrackReject::kBodyCount: return "body_count";
        case DTrackReject::kOutOfRange: return "out_of_range";
        case DTrackReject::kNotRotation: return "not_rotation";
        case DTrackReject::kDuplicate: return "duplicate";
        case DTrackReject::kReplayed: return "replayed";
        case DTrackReject::kCount: break;
    }
    return "?";
}

Pose DTrackBody::pose() const {
    Pose p;
    p.position = position_m;
    p.orientation = glm::normalize(glm::quat_cast(rotation));
    return p;
}

void DTrackFrame::clear() {
    has_frame_counter = has_timestamp = false;
    frame_counter = 0;
    timestamp_s = 0.0;
    calibrated_bodies = flysticks_defined = -1;
    bodies.clear();
    flysticks.clear();
    ignored_lines = unknown_lines = extra_values = 0;
    has_latency = false;
    latency_s = 0.0;
}

const DTrackBody* DTrackFrame::body(int id) const {
    for (const DTrackBody& b : bodies)
        if (b.id == id) return &b;
    return nullptr;
}

DTrackParseResult parse_dtrack_datagram(std::string_view d, DTrackFrame& out) {
    out.clear();
    if (d.size() > kDTrackMaxDatagram) return {DTrackReject::kTooLarge, 0};
    while (!d.empty() && d.back() == '\0') d.remove_suffix(1);  // a C string's terminator sent along
    for (const char c : d)
        if (!text_byte(static_cast<unsigned char>(c))) return {DTrackReject::kNotText, 0};
    bool seen[kLineTypes] = {};
    int line_no = 0, lines = 0;
    std::size_t pos = 0;
    while (pos < d.size()) {
        std::size_t end = d.find('\n', pos);
        if (end == std::string_view::npos) end = d.size();
        std::string_view line = d.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line.find('\r') != std::string_view::npos) return {DTrackReject::kSyntax, line_no};
        if (line.find_first_not_of(" \t") == std::string_view::npos) continue;  // blank line
        ++lines;
        if (const DTrackReject r = parse_line(line, out, seen); r != DTrackReject::kNone) return {r, line_no};
    }
    if (lines == 0) return {DTrackReject::kEmpty, 0};
    if (out.unknown_lines == lines) return {DTrackReject::kUnknownLine, 1};  // nothing DTrack says that tridex reads
    if (out.calibrated_bodies >= 0) {
        if (static_cast<int>(out.bodies.size()) > out.calibrated_bodies) return {DTrackReject::kBodyCount, 0};
        for (const DTrackBody& b : out.bodies)
            if (b.id >= out.calibrated_bodies) return {DTrackReject::kOutOfRange, 0};
    }
    return {};
}

}  // namespace tridex::devices
