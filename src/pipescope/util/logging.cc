#include "pipescope/util/logging.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace pipescope {
namespace {
Verbosity g_verbosity = Verbosity::kNormal;
}  // namespace

void SetupLogging(Verbosity verbosity) {
  g_verbosity = verbosity;
  // Created once; a second call only changes the level.
  auto logger = spdlog::get("pipescope");
  if (!logger) {
    logger = spdlog::stderr_color_mt("pipescope");
    logger->set_pattern("%^[%l]%$ %v");
  }
  switch (verbosity) {
    case Verbosity::kQuiet:
      logger->set_level(spdlog::level::warn);
      break;
    case Verbosity::kNormal:
      logger->set_level(spdlog::level::info);
      break;
    case Verbosity::kVerbose:
      logger->set_level(spdlog::level::debug);
      break;
  }
  spdlog::set_default_logger(logger);
}

Verbosity CurrentVerbosity() { return g_verbosity; }

}  // namespace pipescope
