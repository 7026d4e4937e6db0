// devices/recording_poses.hpp - a recording header's pose sets ("poses") as JSON, checked both ways.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "devices/recording.hpp"

namespace tridex::devices {

/// The header's "poses" array for `poses`. Throws tridex::Error naming `path` and the entry
/// (`header: poses[k].orientation ...`) for a tick that decreases, a time that is not finite, a workpiece out of
/// 0..kMaxRecordedWorkpieces-1, or a pose that is not finite or not unit.
nlohmann::json recorded_poses_json(const std::string& path, const std::vector<RecordedPose>& poses);
/// Reads the header's "poses" value `j` (where: the header's place, for messages). Throws tridex::Error naming the
/// entry and field for anything recorded_poses_json refuses, a missing field or one of the wrong type.
std::vector<RecordedPose> parse_recorded_poses(const std::string& where, const nlohmann::json& j);

}  // namespace tridex::devices
