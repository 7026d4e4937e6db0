// app/commands/recover/recover_command.cpp - `tridex recover JOURNAL`: rebuild a session's model from its journal.
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "app/commands/command.hpp"
#include "app/commands/recover/recover.hpp"

namespace tridex::app {
namespace {

struct RecoverCli {
    std::string journal;
    std::string out = "out/recover";
};

CommandAction setup_recover(CLI::App& cmd) {
    auto o = std::make_shared<RecoverCli>();
    cmd.add_option("JOURNAL", o->journal, "Session journal (OUT/session.tdj of demo or run, or their --journal FILE)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd.add_option("--out", o->out, "Output folder")->capture_default_str();
    return [o] {
        run_recover(o->journal, o->out);
        return 0;
    };
}

const CommandRegistration kRegistration{
    {"recover",
     "Rebuild a session's model from its journal (after a crash or power loss): sculpted.ply, report.json", 40,
     setup_recover}};

}  // namespace
}  // namespace tridex::app
