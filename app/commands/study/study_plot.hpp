// app/commands/study/study_plot.hpp - the per-group plot of `tridex study analyze`: each trial's deviation along the tube.
#pragma once

#include <string>
#include <vector>

namespace tridex::app::study {

struct TrialAnalysis;

/// Draws one line per trial of `trials` (one group's): x = progress along the tube (the tube from 0 to 1, the funnels
/// beyond; axis -0.2..1.2, grid every 0.2), y = deviation in mm per tick, the mean of the wand's top and bottom points'
/// deviations (TrialAnalysis::deviation_m: what the CSV's deviation_m averages; a trial's max_deviation_m is the worse
/// single point, up to twice the plotted peak when only one point goes through the wall), axis 0..a rounded maximum,
/// grid every fifth of it, labelled with digits; a legend of participant and trial right of the plot, as wide as its
/// longest label. Writes a PNG 560 px high, the plot 780 px wide plus its margins, to `path` (renderer::write_png).
/// Lines are coloured by trial in turn. Throws tridex::Error "<path>: ..." when the file cannot be written.
void plot_group_deviation(const std::string& path, const std::vector<const TrialAnalysis*>& trials);

}  // namespace tridex::app::study
