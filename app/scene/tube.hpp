// app/scene/tube.hpp - the navigation tube of the training study (Singapogu 2007, 4.2.1 and 4.3.2): a circular
// section swept along a spline spine, entry and exit funnels, start and end caps; analytic, with the contact
// point of a tool point (its god-object on the tube's inner wall) for the offline deviation analysis.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace tridex::app::study {

/// The tube of a study scene, world metres.
struct TubeSpec {
    std::string name = "tube";          ///< a name for messages and reports
    /// Control points of the spine (>= 2; consecutive points >= 1 mm apart; bends no tighter than kMinBendRadii
    /// times radius_m).
    std::vector<Vec3> spine_m;
    double radius_m = 0.02;             ///< inner radius of the circular section, (1 mm, 0.2 m]
    int samples_per_segment = 32;       ///< polyline samples per spline segment, 4..512
    double funnel_length_m = 0.04;      ///< length of each funnel along the spine's end tangent, [0, 0.5] m
    double funnel_mouth_m = 0.08;       ///< side of a funnel's square mouth, >= 2 radius_m
    double cap_size_m = 0.10;           ///< side of a square cap, >= funnel_mouth_m
    double cap_thickness_m = 0.004;     ///< thickness of a cap (a thin box), (0, 0.05] m
    double touch_tolerance_m = 0.003;   ///< how close a tool point must come to a cap to touch it, [0, 0.05] m
};

/// The tightest bend of a spine: where its radius of curvature is smallest.
struct SpineBend {
    double radius_m = INFINITY;  ///< the smallest radius of curvature, m (infinite for a straight spine)
    std::size_t segment = 0;     ///< the spline segment it lies on: between control points segment and segment + 1
    double t = 0.0;              ///< the segment's parameter there, [0, 1]
};

/// The tightest bend of the uniform Catmull-Rom spline through `spine_m` (>= 2 points, the end tangents as Tube
/// builds them), from the spline's analytic first and second derivatives at 257 parameters per segment:
/// radius = |c'|^3 / |c' x c''|.
SpineBend tightest_bend(const std::vector<Vec3>& spine_m);

/// A spine must bend no tighter than this many tube radii: a circular section swept along a bend tighter than
/// its radius folds its inner wall over itself, and a point near the inner wall no longer has one closest
/// spine point.
inline constexpr double kMinBendRadii = 1.5;

/// Reads a tube object (fields as TubeSpec; `spine_m` required, the rest optional). Throws tridex::Error
/// "<source>: field '<prefix>.<name>': <rule>" for a missing, ill-typed or out-of-range field or an unknown one.
TubeSpec parse_tube(const nlohmann::json& j, const std::string& source, const std::string& prefix = "tube");

/// The spec as JSON (parse_tube reads it back to the same spec).
nlohmann::json tube_to_json(const TubeSpec& spec);

/// An identifier of the tube's geometry: the CRC-32 (IEEE) of tube_to_json's compact text.
std::uint32_t tube_id(const TubeSpec& spec);

/// Two unit vectors u, v spanning the plane normal to the unit vector t: u = unit(t x up), v = u x t, with up =
/// world +y (world +x when t is within about 25 degrees of +-y). The frame of the caps' squares and the funnels'
/// square sections.
void plane_axes(const Vec3& t, Vec3& u, Vec3& v);

/// Where a point lies relative to the spine.
struct SpineProjection {
    double s_m = 0.0;        ///< arc length of the closest spine point; < 0 in the entry funnel, > length in the exit
    Vec3 centre_m{0.0};      ///< the closest point on the (extended) spine
    Vec3 tangent{1, 0, 0};   ///< unit tangent there
    double distance_m = 0.0; ///< distance from the point to centre_m (across the spine), m
};

/// The tube's geometry: the spine as a uniform Catmull-Rom spline through the control points, sampled into a
/// polyline and extended straight along its end tangents through the funnels and caps.
class Tube {
public:
    /// Builds the geometry; throws tridex::Error as parse_tube's rules for an invalid spec ("tube: ...").
    explicit Tube(TubeSpec spec);

    const TubeSpec& spec() const { return spec_; }  ///< the spec it was built from (m)
    /// Arc length of the spine from its first to its last control point, m.
    double length_m() const { return length_m_; }
    /// The closest point of the extended spine to p.
    SpineProjection project(const Vec3& p) const;
    /// The point of the extended spine at arc length s (m; clamped to the extension's ends).
    Vec3 point_at(double s_m) const;
    /// Unit tangent of the spine at arc length s.
    Vec3 tangent_at(double s_m) const;
    /// Free radius of the passage at arc length s: radius_m along the tube, growing linearly to half the mouth
    /// over each funnel (the funnel's square section measured by its inscribed circle), half the mouth beyond.
    double passage_radius_m(double s_m) const;
    /// The contact point of a tool point p on the passage wall: p itself while p is inside the passage, else the
    /// closest wall point (the god-object of a point that crossed the smooth wall), m.
    Vec3 collision_point(const Vec3& p) const;
    /// |p - collision_point(p)|, m (0 inside the passage).
    double deviation_m(const Vec3& p) const;
    /// Whether p touches the start cap (at the entry funnel's mouth) / the end cap (at the exit funnel's mouth):
    /// within touch_tolerance_m of the cap's thin box.
    bool touches_start_cap(const Vec3& p) const;
    bool touches_end_cap(const Vec3& p) const;
    /// Arc length of the start cap's and end cap's centre, m.
    double start_cap_s_m() const;
    double end_cap_s_m() const;

private:
    bool touches_cap(const Vec3& p, double s_cap) const;

    TubeSpec spec_;
    std::vector<Vec3> points_;    ///< the extended polyline
    std::vector<double> arc_;     ///< arc length of each polyline point, 0 at the first control point
    double length_m_ = 0.0;
};

}  // namespace tridex::app::study
