// The command table (app/commands/command.hpp): registration, dispatch and the exit codes a command's errors map to.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands/command.hpp"
#include "core/text/nearest_name.hpp"
#include "app/support/device_lost.hpp"
#include "core/error.hpp"

namespace tridex::app {
namespace {

// A command whose action records its option and then does what `what` says: return 7, or throw.
struct Probe {
    std::string what = "ok";
    int runs = 0;
    double length_m = 0.0;
    int count = 0;
};

Probe& probe() {
    static Probe p;
    return p;
}

const CommandRegistration kProbe{{"probe", "a test command", 5, [](CLI::App& cmd) -> CommandAction {
                                      cmd.add_option("--what", probe().what, "ok, error, lost, memory or internal");
                                      cmd.add_option("--length-m", probe().length_m, "a length, m");
                                      cmd.add_option("--count", probe().count, "a count");
                                      return [] {
                                          ++probe().runs;
                                          const std::string& w = probe().what;
                                          if (w == "error") throw Error("probe: a bad input");
                                          if (w == "lost") throw DeviceLostError("probe: the device vanished");
                                          if (w == "memory") throw std::bad_alloc();
                                          if (w == "internal") throw std::runtime_error("probe: a bug");
                                          return 7;
                                      };
                                  }}};

int run(std::vector<std::string> words) {
    std::vector<char*> argv;
    static std::string exe = "tridex";
    argv.push_back(exe.data());
    for (std::string& w : words) argv.push_back(w.data());
    return run_command_line(static_cast<int>(argv.size()), argv.data());
}

TEST(CommandTable, TheChosenCommandRunsWithItsOptions) {
    probe() = Probe{};
    EXPECT_EQ(run({"probe"}), 7);
    EXPECT_EQ(probe().runs, 1);
    EXPECT_EQ(run({"probe", "--what", "ok"}), 7);
    EXPECT_EQ(probe().runs, 2);
}

TEST(CommandTable, ErrorsBecomeTheDocumentedExitCodes) {
    probe() = Probe{};
    EXPECT_EQ(run({"probe", "--what", "error"}), 2);
    EXPECT_EQ(run({"probe", "--what", "lost"}), 4);
    EXPECT_EQ(run({"probe", "--what", "memory"}), 3);
    EXPECT_EQ(run({"probe", "--what", "internal"}), 1);
    EXPECT_EQ(probe().runs, 4);
}

TEST(CommandTable, BadCommandLinesExitTwoWithoutRunning) {
    probe() = Probe{};
    EXPECT_EQ(run({"nosuch"}), 2);
    EXPECT_EQ(run({"--nosuch"}), 2);
    EXPECT_EQ(run({"probe", "--nosuch"}), 2);
    EXPECT_EQ(run({}), 2);  // a command is required
    EXPECT_EQ(probe().runs, 0);
    EXPECT_EQ(run({"probe", "--help"}), 0);
    EXPECT_EQ(probe().runs, 0);
}

TEST(CommandTable, AMistypedCommandOrOptionGetsTheNearestName) {
    probe() = Probe{};
    testing::internal::CaptureStderr();
    EXPECT_EQ(run({"prob"}), 2);
    std::string said = testing::internal::GetCapturedStderr();
    EXPECT_NE(said.find("unknown command 'prob' (did you mean 'probe'?)"), std::string::npos) << said;
    // The option is named, not its value first (CLI11 lists extras as "64 --lenght-m").
    testing::internal::CaptureStderr();
    EXPECT_EQ(run({"probe", "--lenght-m", "64"}), 2);
    said = testing::internal::GetCapturedStderr();
    EXPECT_NE(said.find("unknown option '--lenght-m' for probe (did you mean '--length-m'?) (see tridex probe --help)"),
              std::string::npos)
        << said;
    testing::internal::CaptureStderr();
    EXPECT_EQ(run({"probe", "--zzzzzzzzzz=3"}), 2);
    said = testing::internal::GetCapturedStderr();
    EXPECT_NE(said.find("unknown option '--zzzzzzzzzz' for probe (see"), std::string::npos) << said;
    EXPECT_EQ(probe().runs, 0);
    EXPECT_EQ(nearest_name("x", {"y", "z"}), "");
    EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
}

// Numbers on the command line are decimal, whole and finite, for every command's options.
TEST(CommandTable, NumbersAreDecimalWholeAndFinite) {
    probe() = Probe{};
    EXPECT_EQ(run({"probe", "--length-m", "2.5e-3", "--count", "-7"}), 7);
    EXPECT_DOUBLE_EQ(probe().length_m, 2.5e-3);
    EXPECT_EQ(probe().count, -7);
    for (const char* bad : {"0x10", "inf", "nan", "1e400", "12abc", "1,5", ""})
        EXPECT_EQ(run({"probe", "--length-m", bad}), 2) << bad;
    for (const char* bad : {"0x10", "1.5", "1e3"}) EXPECT_EQ(run({"probe", "--count", bad}), 2) << bad;
    EXPECT_EQ(probe().runs, 1);
}

TEST(CommandTable, ListsByRankAndRefusesDuplicatesAndBlanks) {
    const std::vector<Command> all = registered_commands();
    ASSERT_FALSE(all.empty());
    for (std::size_t i = 1; i < all.size(); ++i)
        EXPECT_TRUE(all[i - 1].rank < all[i].rank || (all[i - 1].rank == all[i].rank && all[i - 1].name < all[i].name));
    const auto setup = [](CLI::App&) -> CommandAction { return [] { return 0; }; };
    EXPECT_THROW(register_command({"probe", "again", 1, setup}), std::logic_error);
    EXPECT_THROW(register_command({"", "blank", 1, setup}), std::logic_error);
    EXPECT_THROW(register_command({"nosetup", "no setup", 1, nullptr}), std::logic_error);
}

}  // namespace
}  // namespace tridex::app
