// app/commands/study/study_analyze.cpp - the per-trial measures of the study from its recordings.
#include "app/commands/study/study_analyze.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "app/support/output_dir.hpp"
#include "app/commands/study/study_plot.hpp"
#include "app/scene/study_recording.hpp"
#include "app/scene/study_scene.hpp"
#include "core/error.hpp"

namespace tridex::app::study {

namespace {

std::string hex(std::uint32_t v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "%08x", v);
    return buf;
}

std::vector<std::string> find_recordings(const std::vector<std::string>& inputs) {
    std::vector<std::string> files;
    for (const std::string& in : inputs) {
        std::error_code ec;
        if (std::filesystem::is_directory(in, ec)) {
            std::vector<std::string> found;
            for (const auto& e : std::filesystem::recursive_directory_iterator(in, ec))
                if (e.is_regular_file() && e.path().extension() == ".trdx") found.push_back(e.path().string());
            if (found.empty()) throw Error(in + ": no recordings (*.trdx) in this folder");
            std::sort(found.begin(), found.end());
            files.insert(files.end(), found.begin(), found.end());
        } else if (std::filesystem::is_regular_file(in, ec)) {
            files.push_back(in);
        } else {
            throw Error(in + ": no such recording or folder");
        }
    }
    return files;
}

}  // namespace

TrialAnalysis analyze_trial(const devices::Recording& rec, const Tube& tube, const std::string& path) {
    const StudyTag tag = read_tag(rec.header, path);
    const std::uint32_t ref = tube_id(tube.spec());
    if (tag.tube_id != ref)
        throw Error(path + ": recorded against tube '" + tag.tube_name + "' (id " + hex(tag.tube_id) +
                    "), not the reference tube '" + tube.spec().name + "' (id " + hex(ref) + "); not analysed");
    const auto& ticks = rec.ticks;
    auto both = [&](std::size_t i, bool start) {
        return start ? tube.touches_start_cap(ticks[i].top_m) && tube.touches_start_cap(ticks[i].bottom_m)
                     : tube.touches_end_cap(ticks[i].top_m) && tube.touches_end_cap(ticks[i].bottom_m);
    };
    std::size_t first_start = ticks.size();
    for (std::size_t i = 0; i < ticks.size() && first_start == ticks.size(); ++i)
        if (ticks[i].valid && both(i, true)) first_start = i;
    if (first_start == ticks.size()) throw Error(path + ": both tool points never touch the start cap");
    std::size_t end = ticks.size();
    for (std::size_t i = first_start + 1; i < ticks.size() && end == ticks.size(); ++i)
        if (ticks[i].valid && both(i, false)) end = i;
    if (end == ticks.size()) throw Error(path + ": both tool points never touch the end cap after the start cap");
    std::size_t start = first_start;
    for (std::size_t i = first_start; i < end; ++i)
        if (ticks[i].valid && both(i, true)) start = i;

    TrialAnalysis a;
    a.row.participant = tag.participant;
    a.row.group = tag.group;
    a.row.trial = tag.trial;
    a.row.time_s = ticks[end].t_s - ticks[start].t_s;
    double top = 0.0, bottom = 0.0, worst = 0.0;
    std::size_t n = 0;
    for (std::size_t i = start; i <= end; ++i) {
        if (!ticks[i].valid) continue;
        const double dt = tube.deviation_m(ticks[i].top_m), db = tube.deviation_m(ticks[i].bottom_m);
        top += dt;
        bottom += db;
        worst = std::max({worst, dt, db});
        ++n;
        a.progress.push_back(tube.project(0.5 * (ticks[i].top_m + ticks[i].bottom_m)).s_m / tube.length_m());
        a.deviation_m.push_back(0.5 * (dt + db));
    }
    a.row.deviation_top_m = top / static_cast<double>(n);
    a.row.deviation_bottom_m = bottom / static_cast<double>(n);
    a.row.deviation_m = 0.5 * (a.row.deviation_top_m + a.row.deviation_bottom_m);
    a.row.max_deviation_m = worst;
    return a;
}

std::vector<TrialAnalysis> run_study_analyze(const StudyAnalyzeOptions& options) {
    const StudyScene scene = read_study_scene(options.scene.empty() ? default_study_scene_path() : options.scene);
    const Tube tube(scene.tube);
    const std::vector<std::string> files = find_recordings(options.inputs);
    if (files.empty()) throw Error("study analyze: no recordings given");
    prepare_output_dir(options.out, "--out");
    std::vector<TrialAnalysis> trials;
    for (const std::string& f : files) {
        trials.push_back(analyze_trial(devices::read_recording(f), tube, f));
        const TrialRow& r = trials.back().row;
        std::printf("%s: %s %s trial %d: %.2f s, deviation %.2f mm (max %.2f mm)\n", f.c_str(), r.participant.c_str(),
                    r.group.c_str(), r.trial, r.time_s, r.deviation_m * 1e3, r.max_deviation_m * 1e3);
    }
    std::sort(trials.begin(), trials.end(), [](const TrialAnalysis& a, const TrialAnalysis& b) {
        return std::tie(a.row.group, a.row.participant, a.row.trial) < std::tie(b.row.group, b.row.participant, b.row.trial);
    });
    for (std::size_t i = 1; i < trials.size(); ++i)
        if (trials[i].row.participant == trials[i - 1].row.participant && trials[i].row.trial == trials[i - 1].row.trial &&
            trials[i].row.group == trials[i - 1].row.group)
            throw Error("study analyze: participant '" + trials[i].row.participant + "' trial " +
                        std::to_string(trials[i].row.trial) + " is recorded twice");
    std::vector<TrialRow> rows;
    for (const TrialAnalysis& t : trials) rows.push_back(t.row);
    const std::filesystem::path out(options.out);
    write_trial_csv((out / "study_trials.csv").string(), rows);
    for (const std::string& g : study_groups()) {
        std::vector<const TrialAnalysis*> mine;
        for (const TrialAnalysis& t : trials)
            if (t.row.group == g) mine.push_back(&t);
        if (!mine.empty()) plot_group_deviation((out / ("deviation_" + g + ".png")).string(), mine);
    }
    return trials;
}

}  // namespace tridex::app::study
