// app/scene/study_objects.cpp - meshes, contact and colours of the study scene's objects.
#include "app/scene/study_objects.hpp"

#include <cmath>
#include <numbers>
#include <utility>

#include "core/error.hpp"

namespace tridex::app::study {

namespace {

// Appends a strip of rings (each `k` points around the spine, in the order of increasing angle from u to v)
// joined ring to ring along the spine: quads split in two, facing away from the spine for rings ordered by
// increasing s.
void add_strip(TriMesh& m, const std::vector<std::vector<Vec3>>& rings) {
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    const std::size_t k = rings.front().size();
    for (const auto& r : rings) m.positions.insert(m.positions.end(), r.begin(), r.end());
    for (std::size_t i = 0; i + 1 < rings.size(); ++i)
        for (std::size_t j = 0; j < k; ++j) {
            const auto a = static_cast<std::uint32_t>(base + i * k + j), b = static_cast<std::uint32_t>(base + (i + 1) * k + j);
            const auto c = static_cast<std::uint32_t>(base + (i + 1) * k + (j + 1) % k),
                       d = static_cast<std::uint32_t>(base + i * k + (j + 1) % k);
            m.triangles.push_back({a, b, c});
            m.triangles.push_back({a, c, d});
        }
}

// The square section of half side h at arc length s: its corners at angles -45, 45, 135, 225 degrees.
std::vector<Vec3> square_ring(const Tube& tube, double s, double h) {
    Vec3 u, v;
    plane_axes(tube.tangent_at(s), u, v);
    const Vec3 c = tube.point_at(s);
    return {c + h * (u - v), c + h * (u + v), c + h * (-u + v), c + h * (-u - v)};
}

TriMesh funnel(const Tube& tube, double s_from, double s_to, double h_from, double h_to) {
    constexpr int kSections = 8;
    std::vector<std::vector<Vec3>> rings;
    for (int i = 0; i <= kSections; ++i) {
        const double f = static_cast<double>(i) / kSections;
        rings.push_back(square_ring(tube, s_from + f * (s_to - s_from), h_from + f * (h_to - h_from)));
    }
    TriMesh m;
    add_strip(m, rings);
    return m;
}

// A closed thin box centred on the spine at arc length s: cap_size_m square, cap_thickness_m along the tangent.
TriMesh cap(const Tube& tube, double s) {
    const TubeSpec& sp = tube.spec();
    const Vec3 t = tube.tangent_at(s), c = tube.point_at(s);
    const double ht = 0.5 * sp.cap_thickness_m;
    const std::vector<Vec3> back = square_ring(tube, s, 0.5 * sp.cap_size_m);
    TriMesh m;
    for (const Vec3& p : back) m.positions.push_back(p - ht * t);
    for (const Vec3& p : back) m.positions.push_back(p + ht * t);
    // Sides as a strip of the two rings; then the two square faces.
    for (std::uint32_t j = 0; j < 4; ++j) {
        const std::uint32_t a = j, b = 4 + j, cc = 4 + (j + 1) % 4, d = (j + 1) % 4;
        m.triangles.push_back({a, b, cc});
        m.triangles.push_back({a, cc, d});
    }
    m.triangles.push_back({0, 2, 1});  // back face (-t)
    m.triangles.push_back({0, 3, 2});
    m.triangles.push_back({4, 5, 6});  // front face (+t)
    m.triangles.push_back({4, 6, 7});
    // Orient every triangle away from the box centre (the ring order decides the strip's winding).
    for (auto& tri : m.triangles) {
        const Vec3 p0 = m.positions[tri[0]], p1 = m.positions[tri[1]], p2 = m.positions[tri[2]];
        if (glm::dot(glm::cross(p1 - p0, p2 - p0), (p0 + p1 + p2) / 3.0 - c) < 0.0) std::swap(tri[1], tri[2]);
    }
    return m;
}

bool touches_wall(const Tube& tube, const Vec3& p, double point_radius_m, double tolerance_m, bool& in_tube) {
    const SpineProjection pr = tube.project(p);
    const double fl = tube.spec().funnel_length_m, len = tube.length_m();
    in_tube = pr.s_m >= 0.0 && pr.s_m <= len;
    if (pr.s_m < -fl || pr.s_m > len + fl) return false;  // beyond the mouths: no wall
    return pr.distance_m + point_radius_m >= tube.passage_radius_m(pr.s_m) - tolerance_m;
}

}  // namespace

const char* to_string(StudyObject o) {
    switch (o) {
        case StudyObject::kTube: return "tube";
        case StudyObject::kEntryFunnel: return "entry_funnel";
        case StudyObject::kExitFunnel: return "exit_funnel";
        case StudyObject::kStartCap: return "start_cap";
        case StudyObject::kEndCap: return "end_cap";
    }
    return "tube";
}

StudyObjectMeshes study_object_meshes(const Tube& tube, int sides) {
    if (sides < 8) throw Error("study_object_meshes: sides must be >= 8, got " + std::to_string(sides));
    const TubeSpec& sp = tube.spec();
    StudyObjectMeshes m;
    const int n = sp.samples_per_segment * static_cast<int>(sp.spine_m.size() - 1);
    std::vector<std::vector<Vec3>> rings;
    for (int i = 0; i <= n; ++i) {
        const double s = tube.length_m() * i / n;
        Vec3 u, v;
        plane_axes(tube.tangent_at(s), u, v);
        const Vec3 c = tube.point_at(s);
        std::vector<Vec3> ring;
        for (int j = 0; j < sides; ++j) {
            const double a = 2.0 * std::numbers::pi * j / sides;
            ring.push_back(c + sp.radius_m * (std::cos(a) * u + std::sin(a) * v));
        }
        rings.push_back(std::move(ring));
    }
    add_strip(m.tube, rings);
    const double fl = sp.funnel_length_m, len = tube.length_m();
    if (fl > 0.0) {
        m.entry_funnel = funnel(tube, -fl, 0.0, 0.5 * sp.funnel_mouth_m, sp.radius_m);
        m.exit_funnel = funnel(tube, len, len + fl, sp.radius_m, 0.5 * sp.funnel_mouth_m);
    }
    m.start_cap = cap(tube, tube.start_cap_s_m());
    m.end_cap = cap(tube, tube.end_cap_s_m());
    return m;
}

StudyContact study_contact(const Tube& tube, const Vec3& top_m, const Vec3& bottom_m, double point_radius_m,
                           double tolerance_m) {
    StudyContact c;
    if (!is_finite(top_m) || !is_finite(bottom_m)) return c;
    for (const Vec3& p : {top_m, bottom_m}) {
        bool in_tube = false;
        if (touches_wall(tube, p, point_radius_m, tolerance_m, in_tube)) (in_tube ? c.tube : c.funnels) = true;
    }
    c.start_cap = tube.touches_start_cap(top_m) && tube.touches_start_cap(bottom_m);
    c.end_cap = tube.touches_end_cap(top_m) && tube.touches_end_cap(bottom_m);
    return c;
}

glm::vec4 study_object_colour(StudyObject o, const StudyModel& model, const StudyContact& contact) {
    const bool is_cap = o == StudyObject::kStartCap || o == StudyObject::kEndCap;
    const ObjectLook& look = o == StudyObject::kTube ? model.tube : is_cap ? model.caps : model.funnels;
    const float alpha = is_cap ? 0.85f : 0.4f;
    if (!look.visible) return glm::vec4(0.0f);
    const bool touched = o == StudyObject::kTube          ? contact.tube
                         : o == StudyObject::kStartCap    ? contact.start_cap
                         : o == StudyObject::kEndCap      ? contact.end_cap
                                                          : contact.funnels;
    if (look.colour_on_contact)
        return touched ? glm::vec4(0.90f, 0.12f, 0.10f, alpha) : glm::vec4(0.15f, 0.75f, 0.25f, alpha);
    return is_cap ? glm::vec4(0.75f, 0.75f, 0.80f, alpha) : glm::vec4(0.55f, 0.60f, 0.85f, alpha);
}

const StudyModel& study_model(const StudyScene& scene, const std::string& name, const std::string& what) {
    if (name == "haptic_training") return scene.haptic_training;
    if (name == "visual_training") return scene.visual_training;
    if (name == "test") return scene.test;
    throw Error(what + ": model '" + name + "' is not one of haptic_training, visual_training, test");
}

std::vector<renderer::SceneObject> study_scene_objects(const StudyObjectMeshes& meshes, const StudyModel& model,
                                                       const StudyContact& contact) {
    std::vector<renderer::SceneObject> out;
    const auto all = meshes.all();
    for (int i = 0; i < 5; ++i) {
        const glm::vec4 c = study_object_colour(static_cast<StudyObject>(i), model, contact);
        if (c.a > 0.0f) out.push_back({all[i], c});
    }
    return out;
}

}  // namespace tridex::app::study
