#pragma once

#include <stdexcept>
#include <string>

namespace pipescope {

// Bad usage or input from the user: a missing file, a malformed key, a bad flag. The command
// line turns it into exit status 2. The message must name the file, key or flag at fault.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// A run that went wrong in a way its output would hide: poses that are not finite or run off
// to absurd distances, no structure where the method must build some. The command line ends with
// exit status 1 and the message, and writes no run.
class RunFailedError : public std::runtime_error {
 public:
  explicit RunFailedError(const std::string& message) : std::runtime_error(message) {}
};

// Exit statuses of the command line (GUIDE §5).
inline constexpr int kExitSuccess = 0;
inline constexpr int kExitInternalError = 1;
inline constexpr int kExitInputError = 2;

}  // namespace pipescope
