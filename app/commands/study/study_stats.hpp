// app/commands/study/study_stats.hpp - `tridex study stats`: the thesis's statistics (Singapogu 2007, 4.4, Tables 5-7)
// over a per-trial table: Spearman's rho of time against deviation per group, and the Mann-Whitney U test
// between the groups, per trial and on per-participant means.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/scene/trial_table.hpp"

namespace tridex::app::study {

/// Options of `tridex study stats FILE.csv --out DIR`.
struct StudyStatsOptions {
    std::string csv;                 ///< the trial table (read_trial_csv)
    std::string out = "out/study";   ///< folder for study_stats.json and study_stats.txt
};

/// The statistics as JSON (NaN written as null):
/// {"groups": {g: {"trials", "participants", "median_time_s", "median_deviation_m"}},
///  "spearman": {g: r}, "spearman_detail": {g: {"n", "r", "p_t"}},
///  "mann_whitney": {"time_s": {"U", "z", "p_normal", "p_exact", "U1", "U2", "n1", "n2", "group1", "group2",
///                              "mean_U", "sd_U", "ties"}, "deviation_m": {...}},
///  "per_participant": {"participants": {id: {"group", "trials", "time_s", "deviation_m"}}, "spearman": {...},
///                      "spearman_detail": {...}, "mann_whitney": {...}}}
/// U1 is the U of group1 ("haptic"), U = min(U1, U2). Rows must satisfy read_trial_csv's rules (both groups with
/// at least two trials); throws tridex::Error otherwise.
nlohmann::json study_stats_json(const std::vector<TrialRow>& rows);

/// A plain-text report of study_stats_json's result, laid out like the thesis's Tables 5-7 (Spearman per group,
/// then Mann-Whitney U for time and deviation), per trial and per participant.
std::string study_stats_table(const nlohmann::json& stats);

/// Reads the table, writes OUT/study_stats.json and OUT/study_stats.txt, and prints the table. Throws
/// tridex::Error (one line naming the file, line and field) on a bad table or an unwritable --out.
void run_study_stats(const StudyStatsOptions& options);

}  // namespace tridex::app::study
