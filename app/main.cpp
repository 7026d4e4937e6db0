// app/main.cpp - the `tridex` executable: every subcommand registers itself in the command table
// (app/commands/command.hpp), which builds the command line, runs the chosen command and maps errors to exit codes.
#include "app/commands/command.hpp"

int main(int argc, char** argv) { return tridex::app::run_command_line(argc, argv); }
