// app/commands/study/study_command.cpp - `tridex study stats|analyze|run`: the training study.
#include <CLI/CLI.hpp>

#include <memory>

#include "app/commands/command.hpp"
#include "app/commands/study/study_cli.hpp"

namespace tridex::app {
namespace {

CommandAction setup_study(CLI::App& cmd) {
    auto o = std::make_shared<study::StudyCommand>();
    study::add_study_options(cmd, *o);
    return [o] {
        study::run_study_command(*o);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"study", "The training study of Singapogu's thesis (ch. 4): tube scenes, protocol, analysis, statistics", 80,
     setup_study}};

}  // namespace
}  // namespace tridex::app
