#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace pipescope {

// A subcommand adds its flags to the CLI11 app it is given and returns the function that runs
// it once the command line has been parsed. The function returns the exit status.
using SubcommandRunner = std::function<int()>;
using SubcommandSetup = SubcommandRunner (*)(CLI::App* command);

struct Subcommand {
  const char* name;
  const char* description;
  SubcommandSetup setup;
};

// One per file in this folder.
SubcommandRunner SetupEvaluateCommand(CLI::App* command);
SubcommandRunner SetupSimulateCommand(CLI::App* command);
SubcommandRunner SetupGainmaskCommand(CLI::App* command);
SubcommandRunner SetupUndistortCommand(CLI::App* command);
SubcommandRunner SetupRefscaleCommand(CLI::App* command);
SubcommandRunner SetupCalibrateCommand(CLI::App* command);
SubcommandRunner SetupOdometryCommand(CLI::App* command);
SubcommandRunner SetupMosaicCommand(CLI::App* command);
SubcommandRunner SetupMapCommand(CLI::App* command);
SubcommandRunner SetupReportCommand(CLI::App* command);
SubcommandRunner SetupLocateCommand(CLI::App* command);
SubcommandRunner SetupDemoCommand(CLI::App* command);

// Runs a whole command line (`args[0]` is the program's name) as main() would and returns its
// exit status: how `demo` chains the other subcommands.
int RunCommandLine(const std::vector<std::string>& args);

}  // namespace pipescope
