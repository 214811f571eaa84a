#pragma once

namespace pipescope {

enum class Verbosity { kQuiet, kNormal, kVerbose };

// Configures the process-wide spdlog logger: warnings and errors always go to stderr, info
// messages unless quiet, debug messages only when verbose.
void SetupLogging(Verbosity verbosity);

Verbosity CurrentVerbosity();

}  // namespace pipescope
