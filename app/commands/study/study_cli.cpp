// app/commands/study/study_cli.cpp - the `tridex study` subcommands.
#include "app/commands/study/study_cli.hpp"

#include <CLI/CLI.hpp>

#include "core/error.hpp"

namespace tridex::app::study {

void add_study_options(CLI::App& study_cmd, StudyCommand& cmd) {
    CLI::App* study = &study_cmd;
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
    cmd.run_cmd = study->add_subcommand(
        "run", "One participant through the protocol (training, then test trials recorded): OUT/<ID>/trial_<n>.trdx");
    cmd.run_cmd->add_option("--participant", cmd.run.participant, "Participant ID (letters, digits, _ or -; no names)")
        ->required();
    cmd.run_cmd->add_option("--group", cmd.run.group, "Training group: haptic or visual")
        ->required()
        ->check(CLI::IsMember({"haptic", "visual"}));
    cmd.run_cmd->add_flag("--simulated", cmd.run.simulated,
                          "Play a scripted participant through the haptic loop (no person, no window)");
    cmd.run_cmd->add_option("--display", cmd.run.display,
                            "Live phases: window, fullscreen, or offscreen (the scripted participant on the simulated "
                            "device, for tests)")
        ->capture_default_str();
    cmd.run_cmd->add_option("--device", cmd.run.device,
                            "Live phases: the device driver (spacemouse, mouse, falcon, falcon-emulator, simulated; default spacemouse in a window)");
    cmd.run_cmd->add_option("--display-config", cmd.run.display_config, "Live phases: a display config file")
        ->check(CLI::ExistingFile);
    cmd.run_cmd->add_flag("--validate", cmd.run.validate, "Live phases: Vulkan validation layer");
    cmd.run_cmd->add_option("--scene", cmd.run.scene, "Study scene (default: assets/study_tube_scene.json)")
        ->check(CLI::ExistingFile);
    cmd.run_cmd->add_option("--seed", cmd.run.seed, "Scripted participant's seed (0: from the ID)")->capture_default_str();
    cmd.run_cmd->add_option("--out", cmd.run.out, "Study folder; the participant's files go to OUT/<ID>/")
        ->capture_default_str();
}

void run_study_command(const StudyCommand& cmd) {
    if (*cmd.stats_cmd) run_study_stats(cmd.stats);
    if (*cmd.analyze_cmd) run_study_analyze(cmd.analyze);
    if (*cmd.run_cmd) run_study_protocol(cmd.run);
}

}  // namespace tridex::app::study
