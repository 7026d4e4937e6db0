// app/commands/study/study_cli.hpp - the `tridex study` subcommands (study_command.cpp here registers them).
#pragma once

#include "app/commands/study/study_analyze.hpp"
#include "app/commands/study/study_run.hpp"
#include "app/commands/study/study_stats.hpp"

namespace CLI {
class App;
}

namespace tridex::app::study {

/// What the `study` subcommands parse into.
struct StudyCommand {
    StudyStatsOptions stats;
    CLI::App* stats_cmd = nullptr;
    StudyAnalyzeOptions analyze;
    CLI::App* analyze_cmd = nullptr;
    StudyRunOptions run;
    CLI::App* run_cmd = nullptr;
};

/// Declares `study stats FILE.csv [--out DIR]` `study analyze DIR... [--scene FILE] [--out DIR]` and
/// `study run --participant ID --group haptic|visual [--simulated] [--scene FILE] [--seed N] [--out DIR]` on the `study` subcommand `study`, parsing into `cmd` (which must outlive the parse).
void add_study_options(CLI::App& study, StudyCommand& cmd);

/// Runs the chosen study subcommand. Throws tridex::Error (one line) on bad input, as the subcommands do.
void run_study_command(const StudyCommand& cmd);

}  // namespace tridex::app::study
