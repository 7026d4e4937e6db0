// app/scene/trial_table.hpp - the study's per-trial results as a CSV table: one row per test trial,
// written by `tridex study analyze` and read, checked field by field, by `tridex study stats`.
#pragma once

#include <string>
#include <vector>

namespace tridex::app::study {

/// The two training groups of the thesis's experiment (Singapogu 2007, 4.2): haptic or visual training.
inline const std::vector<std::string>& study_groups() {
    static const std::vector<std::string> groups{"haptic", "visual"};
    return groups;
}

/// One test trial's measures (SI units). Deviations are distances from the tool's top and bottom points to
/// their collision points on the reference tube (thesis 4.4).
struct TrialRow {
    std::string participant;          ///< participant ID (letters, digits, '-', '_'; no names)
    std::string group;                ///< "haptic" or "visual"
    int trial = 1;                    ///< trial number within the participant's test, >= 1
    double time_s = 0.0;              ///< start cap to end cap, s (>= 0)
    double deviation_m = 0.0;         ///< mean over ticks of the mean of top and bottom deviations, m (>= 0)
    double deviation_top_m = 0.0;     ///< mean deviation of the top point, m (>= 0)
    double deviation_bottom_m = 0.0;  ///< mean deviation of the bottom point, m (>= 0)
    double max_deviation_m = 0.0;     ///< largest deviation of either point, m (>= 0)
};

/// The CSV columns, in the order write_trial_csv writes them.
const std::vector<std::string>& trial_csv_columns();

/// Whether `id` is a valid participant ID: 1..64 characters of [A-Za-z0-9_-].
bool valid_participant_id(const std::string& id);

/// Reads a trial table. The header row must name at least participant, group, trial, time_s and deviation_m
/// (any order; the other columns of trial_csv_columns are optional, other columns ignored); blank lines are
/// skipped. Refuses, with tridex::Error "<path>:<line>: field '<column>': <what>", a missing column, a row
/// with too few or too many fields, a bad participant ID, an unknown group, a non-integer or non-positive
/// trial, a non-numeric, non-finite or negative measure, a participant in both groups, a repeated
/// (participant, trial), and, naming the file and the group, a group with fewer than two trials.
std::vector<TrialRow> read_trial_csv(const std::string& path);

/// Writes rows as CSV (header = trial_csv_columns, numbers with 9 significant digits) atomically.
/// Throws tridex::Error "<path>: ..." when the file cannot be written.
void write_trial_csv(const std::string& path, const std::vector<TrialRow>& rows);

}  // namespace tridex::app::study
