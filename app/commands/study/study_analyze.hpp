// app/commands/study/study_analyze.hpp - `tridex study analyze`: each test recording replayed against the reference tube
// (the thesis's offline step, Singapogu 2007, 4.4: the collision points of the wand's top and bottom points),
// giving one row per trial of the trial table and a plot per group.
#pragma once

#include <string>
#include <vector>

#include "app/scene/trial_table.hpp"
#include "app/scene/tube.hpp"
#include "devices/recording.hpp"

namespace tridex::app::study {

/// One analysed trial: its table row and its deviation trace.
struct TrialAnalysis {
    TrialRow row;
    std::vector<double> progress;     ///< per analysed tick, arc length of the wand centre / tube length (0..1 in the tube)
    std::vector<double> deviation_m;  ///< per analysed tick, mean of the top and bottom deviations, m
};

/// Analyses one recording against `tube`: the trial runs from the last tick at which both tool points touch the
/// start cap to the first later tick at which both touch the end cap; time_s is the time between them; every
/// tick in between gives the top and bottom points' deviations |p - collision point| (Tube::deviation_m), whose
/// means over the ticks are deviation_top_m and deviation_bottom_m, deviation_m their mean, max_deviation_m the
/// largest. Participant, group and trial come from the recording's study tag. Throws tridex::Error
/// "<path>: ..." when the recording is no study recording, was recorded against another tube (its tube_id is
/// not the reference's: refused, not analysed), or never goes from the start cap to the end cap.
TrialAnalysis analyze_trial(const devices::Recording& rec, const Tube& tube, const std::string& path);

/// Options of `tridex study analyze DIR... [--scene FILE] --out DIR`.
struct StudyAnalyzeOptions {
    std::vector<std::string> inputs;  ///< recordings (*.trdx) or folders searched recursively for them
    std::string scene;                ///< the reference study scene ("" = the bundled one)
    std::string out = "out/study";    ///< where study_trials.csv and deviation_<group>.png go
};

/// Reads every recording, analyses it (analyze_trial), and writes OUT/study_trials.csv (sorted by group,
/// participant, trial) and OUT/deviation_<group>.png (plot_group_deviation). Prints one line per trial.
/// Throws tridex::Error (one line naming the file) on a bad recording, no recordings, or an unwritable --out.
std::vector<TrialAnalysis> run_study_analyze(const StudyAnalyzeOptions& options);

}  // namespace tridex::app::study
