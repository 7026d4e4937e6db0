// app/scene/study_recording.cpp - the study tag in a recording's notes.
#include "app/scene/study_recording.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "app/scene/trial_table.hpp"
#include "core/error.hpp"

namespace tridex::app::study {

std::string tag_notes(const std::string& notes, const StudyTag& tag) {
    nlohmann::json j = nlohmann::json::object();
    if (!notes.empty()) {
        try {
            j = nlohmann::json::parse(notes);
        } catch (const nlohmann::json::parse_error&) {
            throw Error("study recording: the notes are not a JSON object");
        }
        if (!j.is_object()) throw Error("study recording: the notes are not a JSON object");
    }
    j["study"] = {{"participant", tag.participant}, {"group", tag.group}, {"trial", tag.trial}, {"model", tag.model},
                  {"tube_name", tag.tube_name}, {"tube_id", tag.tube_id}};
    return j.dump();
}

StudyTag read_tag(const devices::RecordingHeader& header, const std::string& path) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(header.notes);
    } catch (const nlohmann::json::parse_error&) {
        throw Error(path + ": not a study recording (its notes are not JSON)");
    }
    if (!j.is_object() || !j.contains("study") || !j["study"].is_object())
        throw Error(path + ": not a study recording (no study tag; record with `tridex study run`)");
    const nlohmann::json& s = j["study"];
    auto field = [&](const char* name) -> const nlohmann::json& {
        if (!s.contains(name)) throw Error(path + ": field 'study." + name + "': missing");
        return s[name];
    };
    StudyTag t;
    try {
        t.participant = field("participant").get<std::string>();
        t.group = field("group").get<std::string>();
        t.trial = field("trial").get<int>();
        t.model = field("model").get<std::string>();
        t.tube_name = field("tube_name").get<std::string>();
        t.tube_id = field("tube_id").get<std::uint32_t>();
    } catch (const nlohmann::json::type_error&) {
        throw Error(path + ": a field of 'study' has the wrong type");
    }
    if (!valid_participant_id(t.participant)) throw Error(path + ": field 'study.participant': not an ID");
    const auto& g = study_groups();
    if (std::find(g.begin(), g.end(), t.group) == g.end())
        throw Error(path + ": field 'study.group': unknown group '" + t.group + "'");
    if (t.trial < 1) throw Error(path + ": field 'study.trial': must be >= 1");
    return t;
}

}  // namespace tridex::app::study
