#pragma once
// Errors caused by what the user gave us (a file, a flag, a config field). The command line turns
// them into one line on stderr and exit code 2; every other exception is a bug or a system failure
// (exit code 1).
#include <cstring>
#include <stdexcept>
#include <string>

namespace fovlab {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// A file operation refused by the system (a full disk, a read-only folder, a permission): the
// operator has to act, as on bad input, so it is one line on stderr and exit code 2 too:
// "PATH: OPERATION failed (REASON)".
class FileError : public InputError {
 public:
  FileError(const std::string& path, const std::string& operation, int error_number)
      : InputError(path + ": " + operation + " failed (" + std::strerror(error_number) + ")") {}
};

}  // namespace fovlab
