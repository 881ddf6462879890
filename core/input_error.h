#pragma once
// Errors caused by what the user gave us (a file, a flag, a config field). The command line turns
// them into one line on stderr and exit code 2; every other exception is a bug or a system failure
// (exit code 1).
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

namespace fovlab {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

// A setting out of its range, named by the field of the settings struct that holds it
// ("pyramid_levels 7: expected 2 to 5 pyramid levels"). The renderer knows only its fields; the
// layer that knows where the value came from words it for the user (the CLI as its flag:
// app/cli_support.h reword_setting_error).
class SettingError : public InputError {
 public:
  // `detail` follows the field in the message: " 7: expected ..." or ": expected ...".
  SettingError(const std::string& field_name, const std::string& detail_text)
      : InputError(field_name + detail_text), field(field_name), detail(detail_text) {}
  std::string field;
  std::string detail;
};

// A file operation refused by the system (a full disk, a read-only folder, a permission): the
// operator has to act, as on bad input, so it is one line on stderr and exit code 2 too:
// "PATH: OPERATION failed (REASON)".
class FileError : public InputError {
 public:
  FileError(const std::string& path, const std::string& operation, int error_number)
      : InputError(path + ": " + operation + " failed (" + std::strerror(error_number) + ")") {}
};

// Text from the user's input as a message quotes it: in double quotes, at most 48 bytes, control
// characters, quotes and backslashes as \xNN, so the message stays one readable line whatever the
// input held (a cell with a line break, a 1 MiB line).
inline std::string quoted_input(std::string_view text) {
  constexpr size_t kShown = 48;
  std::string out = "\"";
  for (const char c : text.substr(0, kShown)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7F || c == '"' || c == '\\') {
      static constexpr char hex[] = "0123456789abcdef";
      out += "\\x";
      out += hex[byte >> 4];
      out += hex[byte & 0xF];
    } else {
      out += c;
    }
  }
  out += "\"";
  if (text.size() > kShown) out += " (" + std::to_string(text.size()) + " bytes)";
  return out;
}

}  // namespace fovlab
