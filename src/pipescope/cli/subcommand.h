#pragma once

#include <CLI/CLI.hpp>
#include <functional>

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

}  // namespace pipescope
