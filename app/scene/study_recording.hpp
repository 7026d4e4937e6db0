// app/scene/study_recording.hpp - what a study recording says about itself: its participant, group, trial
// and the tube it was recorded against, kept in the recording header's notes (devices/recording.hpp) beside
// the session settings.
#pragma once

#include <cstdint>
#include <string>

#include "devices/recording.hpp"

namespace tridex::app::study {

/// The study's part of a recording's notes: {"study": {...}} in the notes' JSON object.
struct StudyTag {
    std::string participant;   ///< participant ID (valid_participant_id)
    std::string group;         ///< "haptic" or "visual"
    int trial = 1;             ///< test trial number, >= 1
    std::string model = "test";///< the model recorded ("test")
    std::string tube_name;     ///< TubeSpec::name of the scene's tube
    std::uint32_t tube_id = 0; ///< tube_id of the scene's tube
};

/// `notes` (a JSON object, e.g. the session settings; "" for none) with the tag added under "study".
/// Throws tridex::Error when notes is neither empty nor a JSON object.
std::string tag_notes(const std::string& notes, const StudyTag& tag);

/// The tag of a recording's header. Throws tridex::Error "<path>: not a study recording (...)" when the notes
/// carry no study tag, or "<path>: field 'study.<name>': ..." for a bad field.
StudyTag read_tag(const devices::RecordingHeader& header, const std::string& path);

}  // namespace tridex::app::study
