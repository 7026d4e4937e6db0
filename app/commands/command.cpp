// app/commands/command.cpp - the command table and the `tridex` command line built from it.
#include "app/commands/command.hpp"

#include <CLI/CLI.hpp>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

#include "app/support/crash_report.hpp"
#include "app/support/device_lost.hpp"
#include "app/support/output_dir.hpp"
#include "app/support/stop_signal.hpp"
#include "core/error.hpp"
#include "core/text/nearest_name.hpp"

namespace tridex::app {
namespace {

std::vector<Command>& table() {
    static std::vector<Command> commands;
    return commands;
}

// Mesa's Vulkan drivers (lavapipe) want XDG_RUNTIME_DIR; when the session has none (a plain ssh or CI shell), give
// them a private 0700 folder of this user's instead of letting them warn or fail.
void ensure_runtime_dir() {
    if (std::getenv("XDG_RUNTIME_DIR")) return;
    const std::string dir = "/tmp/tridex-runtime-" + std::to_string(getuid());
    struct stat st {};
    if (mkdir(dir.c_str(), 0700) == 0 || (stat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode) && st.st_uid == getuid()))
        setenv("XDG_RUNTIME_DIR", dir.c_str(), 0);
}

// A first word that names no command: say so and list the commands (CLI11 would only ask for a subcommand).
// Returns 0 when argv may go to the parser, else the exit code.
int check_first_word(int argc, char** argv, const std::vector<Command>& commands) {
    if (argc < 2) return 0;
    const std::string first = argv[1];
    if (first[0] == '-') {
        if (first == "-h" || first == "--help" || first == "--help-all" || first == "--version") return 0;
        std::fprintf(stderr, "tridex: unknown option '%s': a command comes first (see tridex --help)\n", argv[1]);
        return 2;
    }
    std::string names;
    std::vector<std::string> known;
    for (const Command& c : commands) {
        if (c.name == first) return 0;
        names += (names.empty() ? "" : ", ") + c.name;
        known.push_back(c.name);
    }
    const std::string near = nearest_name(first, known);
    std::fprintf(stderr, "tridex: unknown command '%s'%s; the commands are %s (see tridex --help)\n", argv[1],
                 near.empty() ? "" : (" (did you mean '" + near + "'?)").c_str(), names.c_str());
    return 2;
}

// "unknown option '--resolutoin' for demo (did you mean '--resolution'?)" for the first word after the command that
// looks like an option ("-x", "--name", "--name=value") and is none of `sub`'s; "" when every such word is one.
std::string unknown_option_message(const CLI::App& sub, int argc, char** argv) {
    // A command with commands of its own (`tridex study run`) leaves its words to them: CLI11's message says it.
    if (!sub.get_subcommands([](const CLI::App*) { return true; }).empty()) return "";
    std::vector<std::string> known;
    for (const CLI::Option* o : sub.get_options()) {
        for (const std::string& l : o->get_lnames()) known.push_back("--" + l);
        for (const std::string& s : o->get_snames()) known.push_back("-" + s);
    }
    for (int i = 2; i < argc; ++i) {
        std::string word = argv[i];
        if (word == "--") break;
        if (word.size() < 2 || word[0] != '-' || (word[1] >= '0' && word[1] <= '9') || word[1] == '.') continue;
        if (const std::size_t eq = word.find('='); eq != std::string::npos) word.resize(eq);
        if (std::find(known.begin(), known.end(), word) != known.end()) continue;
        const std::string near = nearest_name(word, known);
        return "unknown option '" + word + "' for " + sub.get_name() +
               (near.empty() ? "" : " (did you mean '" + near + "'?)");
    }
    return "";
}

// Digits from `i` on; returns how many.
std::size_t skip_digits(std::string_view t, std::size_t& i) {
    const std::size_t from = i;
    while (i < t.size() && t[i] >= '0' && t[i] <= '9') ++i;
    return i - from;
}

// Whether all of `t` is a decimal number: [+-]digits, and for a real also digits.digits, .digits or digits. with an
// optional exponent [eE][+-]digits. No hexadecimal, no inf or nan, no spaces.
bool is_decimal(std::string_view t, bool integer) {
    std::size_t i = 0;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    std::size_t digits = skip_digits(t, i);
    if (integer) return digits > 0 && i == t.size();
    if (i < t.size() && t[i] == '.') {
        ++i;
        digits += skip_digits(t, i);
    }
    if (digits == 0) return false;
    if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
        ++i;
        if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
        if (skip_digits(t, i) == 0) return false;
    }
    return i == t.size();
}

// One rule for numbers on the command line: decimal text only (no 0x10, no inf or nan), the whole word, finite.
// Ranges stay with each option. Applied to every option CLI11 reads as a number, in every (sub)command.
void require_decimal_numbers(CLI::App& app) {
    for (CLI::Option* o : app.get_options()) {
        const std::string type = o->get_type_name();
        const bool is_int = type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0;
        const bool is_real = type.rfind("FLOAT", 0) == 0 || type.rfind("NUMBER", 0) == 0;
        if (!is_int && !is_real) continue;
        o->check(CLI::Validator(
            [is_int](std::string& text) -> std::string {
                if (!is_decimal(text, is_int))
                    return "'" + text + "' is not a decimal number" + (is_int ? " (a whole number)" : "");
                if (!std::isfinite(std::strtod(text.c_str(), nullptr))) return "'" + text + "' is out of range";
                return "";
            },
            "", "decimal"));
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) require_decimal_numbers(*sub);
}

// Runs the chosen command's action and maps what it throws to an exit code.
int run_action_once(const CommandAction& action) {
    try {
        const int rc = action();
        return stop_signal() ? 128 + stop_signal() : rc;
    } catch (const DeviceLostError& e) {
        std::fprintf(stderr, "tridex: %s\n", e.what());
        return 4;
    } catch (const Error& e) {
        std::fprintf(stderr, "tridex: %s\n", e.what());
        return 2;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "tridex: out of memory; lower --resolution\n");
        return 3;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tridex: internal error: %s\n", e.what());
        return 1;
    }
}

// Runs the command; a command that fails leaves behind none of the output folders it made and wrote nothing into.
int run_action(const CommandAction& action) {
    forget_created_folders();
    const int rc = run_action_once(action);
    if (rc != 0) remove_created_folders_if_empty();
    return rc;
}

}  // namespace

void register_command(Command command) {
    if (command.name.empty() || !command.setup) throw std::logic_error("register_command: a command needs a name and a setup");
    for (const Command& c : table())
        if (c.name == command.name) throw std::logic_error("register_command: '" + command.name + "' registered twice");
    table().push_back(std::move(command));
}

std::vector<Command> registered_commands() {
    std::vector<Command> commands = table();
    std::stable_sort(commands.begin(), commands.end(), [](const Command& a, const Command& b) {
        return a.rank != b.rank ? a.rank < b.rank : a.name < b.name;
    });
    return commands;
}

CommandRegistration::CommandRegistration(Command command) { register_command(std::move(command)); }

int run_command_line(int argc, char** argv) {
    ensure_runtime_dir();
    const std::vector<Command> commands = registered_commands();
    CLI::App cli{"tridex: immersive virtual sculpting with force feedback on a tri-dexel workpiece"};
    cli.require_subcommand(1);
    cli.set_version_flag("--version", "tridex " TRIDEX_VERSION);
    std::vector<std::pair<CLI::App*, CommandAction>> actions;
    for (const Command& c : commands) {
        CLI::App* sub = cli.add_subcommand(c.name, c.summary);
        actions.emplace_back(sub, c.setup(*sub));
    }
    require_decimal_numbers(cli);
    if (const int rc = check_first_word(argc, argv, commands)) return rc;
    try {
        cli.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return cli.exit(e);
    } catch (const CLI::ParseError& e) {
        // Every bad input exits 2 with one line: what was wrong (an unknown option named first, with the nearest
        // known one), else CLI11's message, and where to look.
        const CLI::App* sub = cli.get_subcommands().empty() ? nullptr : cli.get_subcommands().front();
        const std::string unknown = sub ? unknown_option_message(*sub, argc, argv) : "";
        std::fprintf(stderr, "tridex: %s (see tridex %s--help)\n", unknown.empty() ? e.what() : unknown.c_str(),
                     sub ? (sub->get_name() + " ").c_str() : "");
        return 2;
    }
    install_crash_report();   // a crash says what, where, and how to recover the session's journal
    install_stop_handlers();  // SIGINT/SIGTERM end a session cleanly, then exit 128 + signal
    for (const auto& [sub, action] : actions)
        if (*sub) return run_action(action);
    return 2;  // require_subcommand(1) makes this unreachable
}

}  // namespace tridex::app
