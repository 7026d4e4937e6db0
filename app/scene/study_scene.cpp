// app/scene/study_scene.cpp - reading a study scene file.
#include "app/scene/study_scene.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include "app/support/assets.hpp"
#include "core/error.hpp"
#include "core/text/json_refusal.hpp"

namespace tridex::app::study {

namespace {

[[noreturn]] void bad(const std::string& path, const std::string& field, const std::string& rule) {
    throw Error(path + ": field '" + field + "': " + rule);
}

void only_known(const nlohmann::json& j, const std::set<std::string>& known, const std::string& path,
                const std::string& prefix) {
    if (!j.is_object()) bad(path, prefix.empty() ? "(top)" : prefix, "must be an object");
    for (const auto& [key, value] : j.items())
        if (!known.count(key)) bad(path, prefix.empty() ? key : prefix + "." + key, "unknown field");
}

double number(const nlohmann::json& j, const std::string& key, double lo, double hi, const std::string& path,
              const std::string& field, double fallback) {
    if (!j.contains(key)) return fallback;
    if (!j[key].is_number()) bad(path, field, "must be a number");
    const double v = j[key].get<double>();
    if (!std::isfinite(v) || v < lo || v > hi) {
        char buf[128];
        std::snprintf(buf, sizeof buf, "must be in [%g, %g], got %g", lo, hi, v);
        bad(path, field, buf);
    }
    return v;
}

void read_look(const nlohmann::json& j, const std::string& path, const std::string& field, ObjectLook& look) {
    only_known(j, {"visible", "felt", "colour_on_contact"}, path, field);
    for (const auto& [key, member] : {std::pair<const char*, bool ObjectLook::*>{"visible", &ObjectLook::visible},
                                      {"felt", &ObjectLook::felt}, {"colour_on_contact", &ObjectLook::colour_on_contact}})
        if (j.contains(key)) {
            if (!j[key].is_boolean()) bad(path, field + "." + key, "must be true or false");
            look.*member = j[key].get<bool>();
        }
}

}  // namespace

StudyScene read_study_scene(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot read the study scene");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {  // the line, column and what was expected; 1e400 and its field
        throw Error(path + ": not valid JSON: " + json_refusal<nlohmann::json>(text, e));
    }
    only_known(j, {"tube", "wand", "protocol", "models"}, path, "");
    StudyScene s;
    std::error_code ec;
    s.path = std::filesystem::absolute(path, ec).string();
    if (!j.contains("tube")) bad(path, "tube", "missing");
    s.tube = parse_tube(j["tube"], path);
    if (j.contains("wand")) {
        only_known(j["wand"], {"length_m", "radius_m"}, path, "wand");
        s.wand_length_m = number(j["wand"], "length_m", 0.005, 0.2, path, "wand.length_m", s.wand_length_m);
        s.wand_radius_m = number(j["wand"], "radius_m", 0.0005, 0.02, path, "wand.radius_m", s.wand_radius_m);
    }
    if (j.contains("protocol")) {
        const nlohmann::json& p = j["protocol"];
        only_known(p, {"introduction_s", "presentation_s", "test_look_s", "training_s", "test_trials", "trial_timeout_s"},
                   path, "protocol");
        ProtocolTimings& t = s.protocol;
        t.introduction_s = number(p, "introduction_s", 0, 3600, path, "protocol.introduction_s", t.introduction_s);
        t.presentation_s = number(p, "presentation_s", 0, 3600, path, "protocol.presentation_s", t.presentation_s);
        t.test_look_s = number(p, "test_look_s", 0, 3600, path, "protocol.test_look_s", t.test_look_s);
        t.training_s = number(p, "training_s", 0, 7200, path, "protocol.training_s", t.training_s);
        const double trials = number(p, "test_trials", 1, 20, path, "protocol.test_trials", t.test_trials);
        if (trials != std::floor(trials)) bad(path, "protocol.test_trials", "must be a whole number");
        t.test_trials = static_cast<int>(trials);
        t.trial_timeout_s = number(p, "trial_timeout_s", 1, 3600, path, "protocol.trial_timeout_s", t.trial_timeout_s);
    }
    if (j.contains("models")) {
        only_known(j["models"], {"haptic_training", "visual_training", "test"}, path, "models");
        for (const auto& [name, model] : {std::pair<const char*, StudyModel*>{"haptic_training", &s.haptic_training},
                                          {"visual_training", &s.visual_training}, {"test", &s.test}})
            if (j["models"].contains(name)) {
                const std::string f = std::string("models.") + name;
                const nlohmann::json& m = j["models"][name];
                only_known(m, {"tube", "funnels", "caps"}, path, f);
                if (m.contains("tube")) read_look(m["tube"], path, f + ".tube", model->tube);
                if (m.contains("funnels")) read_look(m["funnels"], path, f + ".funnels", model->funnels);
                if (m.contains("caps")) read_look(m["caps"], path, f + ".caps", model->caps);
            }
    }
    if (s.tube.radius_m * 2.0 <= s.wand_radius_m * 2.0)
        bad(path, "tube.radius_m", "the tube must be wider than the wand");
    return s;
}

std::string default_study_scene_path() {
    return bundled_asset("study_tube_scene.json", "the study's tube scene", "pass --scene FILE");
}

}  // namespace tridex::app::study
