#pragma once
// Errors caused by what the user gave us (a file, a flag, a config field). The command line turns
// them into one line on stderr and exit code 2; every other exception is a bug or a system failure
// (exit code 1).
#include <stdexcept>
#include <string>

namespace fovlab {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace fovlab
