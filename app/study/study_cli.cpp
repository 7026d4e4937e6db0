// app/study/study_cli.cpp - the `tridex study` subcommands.
#include "app/study/study_cli.hpp"

#include <CLI/CLI.hpp>

#include "core/error.hpp"

namespace tridex::app::study {

CLI::App* add_study_command(CLI::App& cli, StudyCommand& cmd) {
    CLI::App* study = cli.add_subcommand(
        "study", "The training study of Singapogu's thesis (ch. 4): tube scenes, protocol, analysis, statistics");
    study->require_subcommand(1);
    cmd.stats_cmd = study->add_subcommand(
        "stats", "Spearman's rho per group and Mann-Whitney U between groups over a per-trial CSV table");
    cmd.stats_cmd->add_option("FILE", cmd.stats.csv, "Trial table (participant, group, trial, time_s, deviation_m, ...)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd.stats_cmd->add_option("--out", cmd.stats.out, "Output folder (study_stats.json, study_stats.txt)")
        ->capture_default_str();
    cmd.analyze_cmd = study->add_subcommand(
        "analyze", "Replay test recordings against the reference tube: study_trials.csv and a deviation plot per group");
    cmd.analyze_cmd->add_option("DIR", cmd.analyze.inputs, "Recordings (*.trdx) or folders holding them (searched recursively)")
        ->required();
    cmd.analyze_cmd->add_option("--scene", cmd.analyze.scene, "Reference study scene (default: assets/study_tube_scene.json)")
        ->check(CLI::ExistingFile);
    cmd.analyze_cmd->add_option("--out", cmd.analyze.out, "Output folder (study_trials.csv, deviation_<group>.png)")
        ->capture_default_str();
    return study;
}

void run_study_command(const StudyCommand& cmd) {
    if (*cmd.stats_cmd) run_study_stats(cmd.stats);
    if (*cmd.analyze_cmd) run_study_analyze(cmd.analyze);
}

}  // namespace tridex::app::study
