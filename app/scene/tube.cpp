// app/scene/tube.cpp - the study tube's analytic geometry.
#include "app/scene/tube.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/crc32.hpp"
#include "core/error.hpp"

namespace tridex::app::study {

namespace {

[[noreturn]] void bad(const std::string& source, const std::string& field, const std::string& rule) {
    throw Error(source + ": field '" + field + "': " + rule);
}

double get_number(const nlohmann::json& j, const std::string& key, const std::string& source, const std::string& field,
                  double lo, double hi, bool lo_open, double fallback) {
    if (!j.contains(key)) return fallback;
    const nlohmann::json& v = j.at(key);
    if (!v.is_number()) bad(source, field, "must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x) || x > hi || x < lo || (lo_open && x == lo)) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "must be in %s%g, %g], got %g", lo_open ? "(" : "[", lo, hi, x);
        bad(source, field, buf);
    }
    return x;
}

Vec3 catmull_rom(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, double t) {
    const double t2 = t * t, t3 = t2 * t;
    return 0.5 * ((2.0 * p1) + (-p0 + p2) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                  (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t3);
}

// The control points around segment i (i..i+1) of the uniform Catmull-Rom spline, the ends reflected.
void segment_points(const std::vector<Vec3>& c, std::size_t i, Vec3& p0, Vec3& p3) {
    const std::size_t n = c.size();
    p0 = i == 0 ? 2.0 * c[0] - c[1] : c[i - 1];
    p3 = i + 2 == n ? 2.0 * c[n - 1] - c[n - 2] : c[i + 2];
}

}  // namespace

void plane_axes(const Vec3& t, Vec3& u, Vec3& v) {
    const Vec3 up = std::fabs(t.y) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    u = glm::normalize(glm::cross(t, up));
    v = glm::cross(u, t);
}

SpineBend tightest_bend(const std::vector<Vec3>& c) {
    SpineBend best;
    constexpr int kSamples = 256;
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
        Vec3 p0, p3;
        segment_points(c, i, p0, p3);
        const Vec3 p1 = c[i], p2 = c[i + 1];
        // Derivatives of the cubic 0.5 (2 p1 + a t + b t^2 + d t^3).
        const Vec3 a = -p0 + p2, b = 2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3, d = -p0 + 3.0 * p1 - 3.0 * p2 + p3;
        for (int k = 0; k <= kSamples; ++k) {
            const double t = static_cast<double>(k) / kSamples;
            const Vec3 d1 = 0.5 * (a + 2.0 * t * b + 3.0 * t * t * d), d2 = 0.5 * (2.0 * b + 6.0 * t * d);
            const double speed = glm::length(d1);
            if (speed <= 0.0) continue;
            const double turn = glm::length(glm::cross(d1, d2));
            if (turn <= 0.0) continue;  // straight here
            const double bend = speed * speed * speed / turn;
            if (bend < best.radius_m) best = SpineBend{bend, i, t};
        }
    }
    return best;
}

TubeSpec parse_tube(const nlohmann::json& j, const std::string& source, const std::string& prefix) {
    if (!j.is_object()) bad(source, prefix, "must be an object");
    static const char* known[] = {"name", "spine_m", "radius_m", "samples_per_segment", "funnel_length_m",
                                  "funnel_mouth_m", "cap_size_m", "cap_thickness_m", "touch_tolerance_m"};
    for (const auto& item : j.items()) {
        const std::string& key = item.key();
        if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return key == k; }) == std::end(known))
            bad(source, prefix + "." + key, "unknown field");
    }
    TubeSpec s;
    const std::string f = prefix + ".";
    if (j.contains("name")) {
        if (!j["name"].is_string() || j["name"].get<std::string>().empty()) bad(source, f + "name", "must be a non-empty string");
        s.name = j["name"].get<std::string>();
    }
    if (!j.contains("spine_m")) bad(source, f + "spine_m", "missing (a list of [x, y, z] control points, m)");
    const nlohmann::json& sp = j["spine_m"];
    if (!sp.is_array() || sp.size() < 2) bad(source, f + "spine_m", "must be a list of at least two [x, y, z] points");
    for (std::size_t i = 0; i < sp.size(); ++i) {
        const std::string fi = f + "spine_m[" + std::to_string(i) + "]";
        if (!sp[i].is_array() || sp[i].size() != 3) bad(source, fi, "must be [x, y, z]");
        Vec3 p;
        for (int k = 0; k < 3; ++k) {
            if (!sp[i][k].is_number()) bad(source, fi, "must be [x, y, z] numbers");
            p[k] = sp[i][k].get<double>();
        }
        if (!is_finite(p) || glm::length(p) > 10.0) bad(source, fi, "must be finite and within 10 m of the origin");
        if (!s.spine_m.empty() && glm::length(p - s.spine_m.back()) < 1e-3)
            bad(source, fi, "is less than 1 mm from the point before it");
        s.spine_m.push_back(p);
    }
    s.radius_m = get_number(j, "radius_m", source, f + "radius_m", 1e-3, 0.2, true, s.radius_m);
    s.samples_per_segment = static_cast<int>(
        get_number(j, "samples_per_segment", source, f + "samples_per_segment", 4, 512, false, s.samples_per_segment));
    s.funnel_length_m = get_number(j, "funnel_length_m", source, f + "funnel_length_m", 0.0, 0.5, false, s.funnel_length_m);
    s.funnel_mouth_m = get_number(j, "funnel_mouth_m", source, f + "funnel_mouth_m", 2.0 * s.radius_m, 1.0, false,
                                  std::max(s.funnel_mouth_m, 2.0 * s.radius_m));
    s.cap_size_m = get_number(j, "cap_size_m", source, f + "cap_size_m", s.funnel_mouth_m, 1.0, false,
                              std::max(s.cap_size_m, s.funnel_mouth_m));
    s.cap_thickness_m = get_number(j, "cap_thickness_m", source, f + "cap_thickness_m", 0.0, 0.05, true, s.cap_thickness_m);
    s.touch_tolerance_m =
        get_number(j, "touch_tolerance_m", source, f + "touch_tolerance_m", 0.0, 0.05, false, s.touch_tolerance_m);
    const SpineBend bend = tightest_bend(s.spine_m);
    if (bend.radius_m < kMinBendRadii * s.radius_m) {
        char buf[320];
        std::snprintf(buf, sizeof buf,
                      "the spine bends with a radius of %.1f mm between control points %zu and %zu, under %.1f times "
                      "the tube's radius (%.1f mm), so the tube's inner wall would fold; move the control points "
                      "further apart or flatten the bend",
                      bend.radius_m * 1e3, bend.segment, bend.segment + 1, kMinBendRadii, s.radius_m * 1e3);
        bad(source, f + "spine_m", buf);
    }
    return s;
}

nlohmann::json tube_to_json(const TubeSpec& s) {
    nlohmann::json spine = nlohmann::json::array();
    for (const Vec3& p : s.spine_m) spine.push_back({p.x, p.y, p.z});
    return {{"name", s.name}, {"spine_m", spine}, {"radius_m", s.radius_m}, {"samples_per_segment", s.samples_per_segment},
            {"funnel_length_m", s.funnel_length_m}, {"funnel_mouth_m", s.funnel_mouth_m}, {"cap_size_m", s.cap_size_m},
            {"cap_thickness_m", s.cap_thickness_m}, {"touch_tolerance_m", s.touch_tolerance_m}};
}

std::uint32_t tube_id(const TubeSpec& spec) {
    const std::string text = tube_to_json(spec).dump();
    return crc32_ieee(text.data(), text.size());
}

Tube::Tube(TubeSpec spec) : spec_(std::move(spec)) {
    spec_ = parse_tube(tube_to_json(spec_), "tube");  // one set of rules for files and code
    const std::vector<Vec3>& c = spec_.spine_m;
    const std::size_t n = c.size();
    std::vector<Vec3> curve;
    for (std::size_t i = 0; i + 1 < n; ++i) {
        Vec3 p0, p3;
        segment_points(c, i, p0, p3);
        for (int k = 0; k < spec_.samples_per_segment; ++k)
            curve.push_back(catmull_rom(p0, c[i], c[i + 1], p3, static_cast<double>(k) / spec_.samples_per_segment));
    }
    curve.push_back(c.back());
    const Vec3 t0 = glm::normalize(curve[1] - curve[0]);
    const Vec3 t1 = glm::normalize(curve[curve.size() - 1] - curve[curve.size() - 2]);
    const double ext = spec_.funnel_length_m + spec_.cap_thickness_m + spec_.cap_size_m;  // beyond the caps
    points_.push_back(curve.front() - ext * t0);
    points_.insert(points_.end(), curve.begin(), curve.end());
    points_.push_back(curve.back() + ext * t1);
    arc_.assign(points_.size(), -ext);
    for (std::size_t i = 1; i < points_.size(); ++i) arc_[i] = arc_[i - 1] + glm::length(points_[i] - points_[i - 1]);
    length_m_ = arc_[arc_.size() - 2];
}

SpineProjection Tube::project(const Vec3& p) const {
    SpineProjection best;
    double best_d2 = INFINITY;
    for (std::size_t i = 0; i + 1 < points_.size(); ++i) {
        const Vec3 a = points_[i], ab = points_[i + 1] - a;
        const double len2 = glm::dot(ab, ab);
        if (len2 <= 0.0) continue;
        const double t = std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0);
        const Vec3 q = a + t * ab;
        const double d2 = glm::dot(p - q, p - q);
        if (d2 < best_d2) {
            best_d2 = d2;
            best.s_m = arc_[i] + t * std::sqrt(len2);
            best.centre_m = q;
            best.tangent = ab / std::sqrt(len2);
        }
    }
    best.distance_m = std::sqrt(best_d2);
    return best;
}

Vec3 Tube::point_at(double s) const {
    s = std::clamp(s, arc_.front(), arc_.back());
    const auto it = std::upper_bound(arc_.begin(), arc_.end(), s);
    const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - arc_.begin() - 1, 0)),
                                                points_.size() - 2);
    const double len = arc_[i + 1] - arc_[i];
    return points_[i] + (len > 0.0 ? (s - arc_[i]) / len : 0.0) * (points_[i + 1] - points_[i]);
}

Vec3 Tube::tangent_at(double s) const {
    const double h = 1e-4;
    return glm::normalize(point_at(s + h) - point_at(s - h));
}

double Tube::passage_radius_m(double s) const {
    const double r = spec_.radius_m, mouth = 0.5 * spec_.funnel_mouth_m, f = spec_.funnel_length_m;
    if (s >= 0.0 && s <= length_m_) return r;
    const double beyond = s < 0.0 ? -s : s - length_m_;
    if (f <= 0.0 || beyond >= f) return mouth;
    return r + (mouth - r) * beyond / f;
}

Vec3 Tube::collision_point(const Vec3& p) const {
    const SpineProjection pr = project(p);
    const double r = passage_radius_m(pr.s_m);
    if (pr.distance_m <= r) return p;
    return pr.centre_m + (r / pr.distance_m) * (p - pr.centre_m);
}

double Tube::deviation_m(const Vec3& p) const { return glm::length(p - collision_point(p)); }

double Tube::start_cap_s_m() const { return -spec_.funnel_length_m - 0.5 * spec_.cap_thickness_m; }
double Tube::end_cap_s_m() const { return length_m_ + spec_.funnel_length_m + 0.5 * spec_.cap_thickness_m; }

bool Tube::touches_cap(const Vec3& p, double s_cap) const {
    const Vec3 c = point_at(s_cap), t = tangent_at(s_cap);
    Vec3 u, v;
    plane_axes(t, u, v);
    const Vec3 d = p - c;
    const double tol = spec_.touch_tolerance_m, half = 0.5 * spec_.cap_size_m;
    return std::fabs(glm::dot(d, t)) <= 0.5 * spec_.cap_thickness_m + tol && std::fabs(glm::dot(d, u)) <= half + tol &&
           std::fabs(glm::dot(d, v)) <= half + tol;
}

bool Tube::touches_start_cap(const Vec3& p) const { return touches_cap(p, start_cap_s_m()); }
bool Tube::touches_end_cap(const Vec3& p) const { return touches_cap(p, end_cap_s_m()); }

}  // namespace tridex::app::study
