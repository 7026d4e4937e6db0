// app/commands/study/study_stats.cpp - the study's statistics as JSON and as a thesis-style text table.
#include "app/commands/study/study_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "app/support/json_file.hpp"
#include "app/support/output_dir.hpp"
#include "app/commands/study/rank_tests.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace tridex::app::study {

namespace {

nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

double median(std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// One observation unit (a trial, or a participant's mean) of a group.
struct Unit {
    std::string group;
    double time_s, deviation_m;
};

nlohmann::json mann_whitney_json(const std::vector<Unit>& units, double Unit::*field) {
    const auto& g = study_groups();
    std::vector<double> a, b;
    for (const Unit& u : units) (u.group == g[0] ? a : b).push_back(u.*field);
    const MannWhitneyResult m = mann_whitney(a, b);
    return {{"U", m.u}, {"z", m.z}, {"p_normal", num(m.p_normal)}, {"p_exact", num(m.p_exact)}, {"U1", m.u1},
            {"U2", m.u2}, {"n1", m.n1}, {"n2", m.n2}, {"group1", g[0]}, {"group2", g[1]}, {"mean_U", m.mean_u},
            {"sd_U", m.sd_u}, {"ties", m.ties}};
}

// Spearman (r only, and the detail) and Mann-Whitney over `units` into `j`.
void tests_json(const std::vector<Unit>& units, nlohmann::json& j) {
    j["spearman"] = nlohmann::json::object();
    j["spearman_detail"] = nlohmann::json::object();
    for (const std::string& g : study_groups()) {
        std::vector<double> t, d;
        for (const Unit& u : units)
            if (u.group == g) t.push_back(u.time_s), d.push_back(u.deviation_m);
        if (t.size() < 2) {
            j["spearman"][g] = nullptr;
            j["spearman_detail"][g] = {{"n", t.size()}, {"r", nullptr}, {"p_t", nullptr}, {"p_exact", nullptr}};
            continue;
        }
        const SpearmanResult s = spearman(t, d);
        j["spearman"][g] = num(s.r);
        j["spearman_detail"][g] = {{"n", s.n}, {"r", num(s.r)}, {"p_t", num(s.p_t)}, {"p_exact", num(s.p_exact)}};
    }
    j["mann_whitney"] = {{"time_s", mann_whitney_json(units, &Unit::time_s)},
                         {"deviation_m", mann_whitney_json(units, &Unit::deviation_m)}};
}

std::string fmt(const nlohmann::json& v, const char* f = "%.4f") {
    if (v.is_null()) return "-";
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v.get<double>());
    return buf;
}

std::string section(const nlohmann::json& j, const std::string& unit) {
    std::string s;
    char line[256];
    s += "Spearman rank correlation, time against deviation (" + unit + ")\n";
    std::snprintf(line, sizeof line, "  %-8s %4s %9s %9s %9s\n", "group", "n", "r_s", "p(t)", "p_exact");
    s += line;
    for (const auto& [g, d] : j["spearman_detail"].items()) {
        std::snprintf(line, sizeof line, "  %-8s %4d %9s %9s %9s\n", g.c_str(), d["n"].get<int>(), fmt(d["r"]).c_str(),
                      fmt(d["p_t"]).c_str(), fmt(d["p_exact"]).c_str());
        s += line;
    }
    s += "Mann-Whitney U, " + j["mann_whitney"]["time_s"]["group1"].get<std::string>() + " against " +
         j["mann_whitney"]["time_s"]["group2"].get<std::string>() + " (" + unit + ", two-sided)\n";
    std::snprintf(line, sizeof line, "  %-12s %3s %3s %8s %8s %9s %9s\n", "measure", "n1", "n2", "U", "z", "p_normal",
                  "p_exact");
    s += line;
    for (const char* m : {"time_s", "deviation_m"}) {
        const nlohmann::json& r = j["mann_whitney"][m];
        std::snprintf(line, sizeof line, "  %-12s %3d %3d %8s %8s %9s %9s\n", m, r["n1"].get<int>(), r["n2"].get<int>(),
                      fmt(r["U"], "%.1f").c_str(), fmt(r["z"], "%.3f").c_str(), fmt(r["p_normal"]).c_str(),
                      fmt(r["p_exact"]).c_str());
        s += line;
    }
    return s;
}

}  // namespace

nlohmann::json study_stats_json(const std::vector<TrialRow>& rows) {
    nlohmann::json j;
    std::vector<Unit> trials;
    std::map<std::string, std::vector<const TrialRow*>> by_participant;
    for (const TrialRow& r : rows) {
        trials.push_back({r.group, r.time_s, r.deviation_m});
        by_participant[r.participant].push_back(&r);
    }
    for (const std::string& g : study_groups()) {
        std::vector<double> t, d;
        std::size_t people = 0;
        for (const TrialRow& r : rows)
            if (r.group == g) t.push_back(r.time_s), d.push_back(r.deviation_m);
        for (const auto& [id, rs] : by_participant) people += rs.front()->group == g;
        if (t.size() < 2) throw Error("study stats: group '" + g + "' has fewer than two trials");
        j["groups"][g] = {{"trials", t.size()}, {"participants", people}, {"median_time_s", median(t)},
                          {"median_deviation_m", median(d)}};
    }
    tests_json(trials, j);

    nlohmann::json& pp = j["per_participant"];
    std::vector<Unit> means;
    for (const auto& [id, rs] : by_participant) {
        double t = 0.0, d = 0.0;
        for (const TrialRow* r : rs) t += r->time_s, d += r->deviation_m;
        const double n = static_cast<double>(rs.size());
        means.push_back({rs.front()->group, t / n, d / n});
        pp["participants"][id] = {{"group", rs.front()->group}, {"trials", rs.size()}, {"time_s", t / n},
                                  {"deviation_m", d / n}};
    }
    tests_json(means, pp);
    return j;
}

std::string study_stats_table(const nlohmann::json& stats) {
    std::string s = "Training study statistics (Singapogu 2007, 4.4)\n";
    for (const auto& [g, d] : stats["groups"].items())
        s += "  " + g + ": " + std::to_string(d["trials"].get<int>()) + " trials from " +
             std::to_string(d["participants"].get<int>()) + " participants, median time " +
             fmt(d["median_time_s"], "%.2f") + " s, median deviation " +
             fmt(d["median_deviation_m"].is_null() ? d["median_deviation_m"] : nlohmann::json(d["median_deviation_m"].get<double>() * 1e3), "%.3f") + " mm\n";
    s += "\n" + section(stats, "per trial");
    s += "\n" + section(stats["per_participant"], "per-participant means");
    return s;
}

void run_study_stats(const StudyStatsOptions& options) {
    const std::vector<TrialRow> rows = read_trial_csv(options.csv);
    prepare_output_dir(options.out, "--out");
    const nlohmann::json stats = study_stats_json(rows);
    const std::string table = study_stats_table(stats);
    const std::filesystem::path out(options.out);
    write_json_file((out / "study_stats.json").string(), stats);
    write_file_atomically((out / "study_stats.txt").string(), table);
    std::fputs(table.c_str(), stdout);
}

}  // namespace tridex::app::study
