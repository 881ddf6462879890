#pragma once
// Every command-line option that names a path a command writes is registered here, so that it is
// checked by the output guard (core/output_guard.h) while the command line is parsed, before any
// work, and says in its --help what happens to an existing file. The option carries a named
// validator (output_kind_of reads it back), so a test can list every command's output options from
// the command-line definition itself (SessionRace.EveryOptionThatLooksLikeAnOutputIsRegisteredAsOne,
// tests/protocols/session/session_race_test.cpp): a new output flag
// registered any other way is caught there by its name.
#include <filesystem>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "core/output_guard.h"

namespace fovlab::app {

struct OutputOption {
  OutputTarget target;
  // What the command does with what is already there, for --help: one of the texts below, or the
  // command's own.
  std::string on_existing;
};

inline constexpr const char* kReplacesAFile = "an existing file is replaced";
inline constexpr const char* kWritesIntoAFolder = "made when missing; files of the same names in it are replaced";
inline constexpr const char* kCacheFolder = "made when missing; what is missing is added, nothing else is changed";

CLI::Option* add_output_option(CLI::App& command, const std::string& name, std::string& path, const std::string& help,
                               const OutputOption& output);
CLI::Option* add_output_option(CLI::App& command, const std::string& name, std::filesystem::path& path,
                               const std::string& help, const OutputOption& output);

// The kind of output an option was registered with by add_output_option; none for any other option.
std::optional<OutputKind> output_kind_of(CLI::Option& option);

}  // namespace fovlab::app
