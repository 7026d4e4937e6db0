// app/commands/command.hpp - the command table: each `tridex` subcommand registers itself here, from its own file.
//
// How to add a command: give it a folder app/commands/<name>/ with <name>.{hpp,cpp} doing its work
// (<name>_cli.{hpp,cpp} instead where tests parse its options too: run, study) and <name>_command.cpp (bench/...,
// for the benchmarks) registering it:
//   static const tridex::app::CommandRegistration kRegistration{{"name", "one-line summary", rank, setup}};
// where setup declares the command's options on the CLI11 subcommand it is given and returns the action that
// runs it. Add that file to the `tridex_commands` object library and the others to `tridex_app` (app/CMakeLists.txt);
// nothing else changes.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace tridex::app {

/// What a command does once its options are parsed: returns the process exit code (0 on success). It may throw
/// tridex::Error (exit 2, one line on stderr), DeviceLostError (exit 4) or std::bad_alloc (exit 3).
using CommandAction = std::function<int()>;

/// One subcommand of `tridex`.
struct Command {
    std::string name;     ///< what the user types after `tridex` (lower case, '-' between words)
    std::string summary;  ///< one line for `tridex --help`
    int rank = 100;       ///< position in `tridex --help`: lower first, then by name
    /// Declares the command's options and positionals on `cmd` (CLI11; the table has already set its name and
    /// summary) and returns the action to run when the user chose this command. The options it declares must
    /// stay alive until the action has run: keep them in a std::shared_ptr captured by the action.
    std::function<CommandAction(CLI::App& cmd)> setup;
};

/// Adds `command` to the table. Throws std::logic_error when the name is empty, taken, or setup is empty (a
/// programming error, seen at start-up).
void register_command(Command command);

/// Every registered command, ordered by rank, then name.
std::vector<Command> registered_commands();

/// Registers a command during static initialisation: `static const CommandRegistration reg{{...}};` in the
/// command's own source file (linked into the executable as an object file, so that it is never dropped).
struct CommandRegistration {
    explicit CommandRegistration(Command command);
};

/// The help line of --keep-islands (run, demo): the sessions that sculpt share it.
inline constexpr const char* kKeepIslandsHelp =
    "Keep the specks a cut leaves floating (default: when a stroke ends, pieces it cut loose that are smaller than "
    "the tool's ball are removed; report.json sculpt.islands_removed counts them)";

/// The whole command line: builds a CLI11 parser from the table (`tridex --help` lists every command, `tridex CMD
/// --help` its options), parses argv, runs the chosen command and turns errors into exit codes: 2 for a bad
/// command line or tridex::Error (one line on stderr), 3 out of memory, 4 device lost, 1 internal error, and
/// 128 + N when signal N (SIGINT, SIGTERM) ended the session. Sets XDG_RUNTIME_DIR to a private 0700 folder when
/// the environment has none (Mesa's lavapipe needs one).
int run_command_line(int argc, char** argv);

}  // namespace tridex::app
