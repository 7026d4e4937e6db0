// devices/recording_poses.cpp - a recording header's pose sets as JSON.
#include "devices/recording_poses.hpp"

#include <cmath>

#include "core/error.hpp"
#include "core/pose.hpp"

namespace tridex::devices {
namespace {

// "" when `p` is a usable entry, else what is wrong with it (the field named after `at`).
std::string pose_problem(const std::string& at, const RecordedPose& p, std::uint64_t previous_tick) {
    if (p.tick < previous_tick) return at + ".tick = " + std::to_string(p.tick) + " decreases";
    if (!std::isfinite(p.device_t_s)) return at + ".t_s is not finite";
    if (p.workpiece >= kMaxRecordedWorkpieces)
        return at + ".workpiece is not 0.." + std::to_string(kMaxRecordedWorkpieces - 1);
    if (!is_finite(p.pose.position)) return at + ".position_m is not finite";
    if (!is_unit(p.pose.orientation)) return at + ".orientation is not a unit quaternion";
    return {};
}

}  // namespace

nlohmann::json recorded_poses_json(const std::string& path, const std::vector<RecordedPose>& poses) {
    nlohmann::json out = nlohmann::json::array();
    std::uint64_t prev = 0;
    for (std::size_t k = 0; k < poses.size(); ++k) {
        const RecordedPose& p = poses[k];
        const std::string bad = pose_problem(path + ": header: poses[" + std::to_string(k) + "]", p, prev);
        if (!bad.empty()) throw Error(bad);
        prev = p.tick;
        const Vec3& x = p.pose.position;
        const Quat& q = p.pose.orientation;
        out.push_back({{"tick", p.tick},
                       {"t_s", p.device_t_s},
                       {"workpiece", p.workpiece},
                       {"position_m", {x.x, x.y, x.z}},
                       {"orientation", {q.w, q.x, q.y, q.z}}});
    }
    return out;
}

std::vector<RecordedPose> parse_recorded_poses(const std::string& where, const nlohmann::json& j) {
    if (!j.is_array()) throw Error(where + ": \"poses\" is not an array");
    std::vector<RecordedPose> out;
    std::uint64_t prev = 0;
    for (std::size_t k = 0; k < j.size(); ++k) {
        const std::string at = where + ": poses[" + std::to_string(k) + "]";
        const nlohmann::json& e = j[k];
        if (!e.is_object()) throw Error(at + " is not an object");
        const auto numbers = [&](const char* key, std::size_t n) {
            const auto it = e.find(key);
            if (it == e.end() || !it->is_array() || it->size() != n)
                throw Error(at + "." + key + " missing or not " + std::to_string(n) + " numbers");
            std::vector<double> v;
            for (const nlohmann::json& x : *it) {
                if (!x.is_number()) throw Error(at + "." + key + " missing or not " + std::to_string(n) + " numbers");
                v.push_back(x.get<double>());
            }
            return v;
        };
        RecordedPose p;
        const auto tick = e.find("tick");
        if (tick == e.end() || !tick->is_number_unsigned()) throw Error(at + ".tick missing or not an integer >= 0");
        p.tick = tick->get<std::uint64_t>();
        const auto t = e.find("t_s");
        if (t == e.end() || !t->is_number()) throw Error(at + ".t_s missing or not a number");
        p.device_t_s = t->get<double>();
        const auto w = e.find("workpiece");
        if (w == e.end() || !w->is_number_unsigned() ||
            w->get<std::uint64_t>() >= static_cast<std::uint64_t>(kMaxRecordedWorkpieces))
            throw Error(at + ".workpiece missing or not an integer 0.." + std::to_string(kMaxRecordedWorkpieces - 1));
        p.workpiece = static_cast<std::uint8_t>(w->get<std::uint64_t>());
        const std::vector<double> x = numbers("position_m", 3), q = numbers("orientation", 4);
        p.pose = Pose{Vec3(x[0], x[1], x[2]), Quat(q[0], q[1], q[2], q[3])};
        const std::string bad = pose_problem(at, p, prev);
        if (!bad.empty()) throw Error(bad);
        prev = p.tick;
        out.push_back(p);
    }
    return out;
}

}  // namespace tridex::devices
