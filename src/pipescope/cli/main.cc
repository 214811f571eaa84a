// pipescope: visual odometry and mapping for in-pipe inspection cameras. This file is the table
// of subcommands (GUIDE §5); each subcommand lives in its own file.
#include <glog/logging.h>
#include <malloc.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <exception>
#include <filesystem>
#include <opencv2/core/utils/logger.hpp>
#include <string>
#include <vector>

#include "pipescope/cli/subcommand.h"
#include "pipescope/util/error.h"
#include "pipescope/util/interruption.h"
#include "pipescope/util/logging.h"
#include "pipescope/util/run_report.h"

namespace pipescope {
namespace {

const Subcommand kSubcommands[] = {
    {"demo", "Simulate a short pipe, run odometry, write the report and print where it is",
     SetupDemoCommand},
    {"simulate", "Render a simulated pipe dataset with exact ground truth", SetupSimulateCommand},
    {"odometry", "Visual odometry down a straight pipe (dense: 000 §4, 003 §2)",
     SetupOdometryCommand},
    {"mosaic", "Stitch a dataset's frames at known poses into an appearance map (000 §6.1)",
     SetupMosaicCommand},
    {"map", "Fisheye pipe mapping of straight pipes and networks (001 §III)", SetupMapCommand},
    {"calibrate", "Calibrate the camera from checkerboard images (001 §II)", SetupCalibrateCommand},
    {"gainmask", "Build the gain mask from white-card images (000 §3.2)", SetupGainmaskCommand},
    {"undistort", "Write a dataset's frames rectified to a perspective image",
     SetupUndistortCommand},
    {"refscale", "Measure the reference scale from an image of a circle target (000 §3.3)",
     SetupRefscaleCommand},
    {"evaluate", "Compare an estimated trajectory with ground truth (metrics.json)",
     SetupEvaluateCommand},
    {"report", "Write report.html of a run directory", SetupReportCommand},
    {"locate", "Where a pixel of a frame lies on the wall: distance and clock position",
     SetupLocateCommand},
};

// CLI11 answers a mistyped subcommand with "A subcommand is required"; say what was wrong.
bool IsUnknownSubcommand(int argc, char** argv, std::string* message) {
  if (argc < 2 || argv[1][0] == '-') return false;
  std::string names;
  for (const Subcommand& subcommand : kSubcommands) {
    if (argv[1] == std::string(subcommand.name)) return false;
    names += (names.empty() ? "" : ", ") + std::string(subcommand.name);
  }
  *message = "unknown subcommand '" + std::string(argv[1]) + "'; the subcommands are " + names +
             " (pipescope --help)";
  return true;
}

int RunMain(int argc, char** argv) {
  std::string unknown;
  if (IsUnknownSubcommand(argc, argv, &unknown)) {
    spdlog::error("{}", unknown);
    return kExitInputError;
  }
  CLI::App app{"pipescope: maps pipes from the images of one camera carried through them",
               "pipescope"};
  app.set_version_flag("--version", std::string(PipescopeVersion()));
  app.require_subcommand(1);
  bool verbose = false;
  bool quiet = false;
  app.add_flag("-v,--verbose", verbose, "Log debug messages");
  app.add_flag("-q,--quiet", quiet, "Only warnings and errors; no progress bar");

  SubcommandRunner runner;
  for (const Subcommand& subcommand : kSubcommands) {
    CLI::App* command = app.add_subcommand(subcommand.name, subcommand.description);
    command->fallthrough();  // --verbose / --quiet may follow the subcommand
    SubcommandRunner run = subcommand.setup(command);
    command->callback([&runner, run] { runner = run; });
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitInputError;
  }

  // Frame-sized buffers (3 MB at 1024x768) are allocated and freed many times a frame; by
  // default glibc maps and unmaps each, and the page faults cost the sparse odometry about a
  // fifth of its CPU time (perf). Serving them from the heap and not trimming it reuses the pages.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  SetupLogging(quiet ? Verbosity::kQuiet : verbose ? Verbosity::kVerbose : Verbosity::kNormal);
  // Ceres reports through glog, down to Jacobian dumps of a failed residual; the run's own
  // messages say what went wrong, so glog speaks only with --verbose.
  FLAGS_minloglevel = verbose ? google::GLOG_INFO : google::GLOG_FATAL;
  cv::utils::logging::setLogLevel(verbose ? cv::utils::logging::LOG_LEVEL_WARNING
                                          : cv::utils::logging::LOG_LEVEL_ERROR);
  try {
    return runner();
  } catch (const InputError& error) {
    spdlog::error("{}", error.what());
    return kExitInputError;
  } catch (const std::filesystem::filesystem_error& error) {
    // A folder that cannot be written or read (permissions, full disk) is the user's to fix;
    // the message names the paths.
    spdlog::error("{}", error.what());
    return kExitInputError;
  } catch (const RunFailedError& error) {
    spdlog::error("the run failed: {}; no run was written", error.what());
    return kExitInternalError;
  } catch (const std::exception& error) {
    spdlog::error("internal error: {}", error.what());
    return kExitInternalError;
  }
}

}  // namespace

int RunCommandLine(const std::vector<std::string>& args) {
  std::vector<std::string> copies = args;
  std::vector<char*> argv;
  for (std::string& arg : copies) argv.push_back(arg.data());
  argv.push_back(nullptr);
  return RunMain(static_cast<int>(copies.size()), argv.data());
}

}  // namespace pipescope

int main(int argc, char** argv) {
  // First, before OpenCV or Ceres start threads: they must inherit the blocked signals.
  pipescope::InstallInterruptionHandler();
  return pipescope::RunMain(argc, argv);
}
