#include "app/output_options.h"

namespace fovlab::app {
namespace {

const char* validator_name(OutputKind kind) {
  switch (kind) {
    case OutputKind::file:
      return "fovlab-output-file";
    case OutputKind::image_file:
      return "fovlab-output-image";
    case OutputKind::folder:
      return "fovlab-output-folder";
  }
  return "";
}

template <typename Path>
CLI::Option* add(CLI::App& command, const std::string& name, Path& path, const std::string& help,
                 const OutputOption& output) {
  const OutputTarget target = output.target;
  // CLI11 puts the option's name before the message ("--json: ...").
  CLI::Validator guard([target](std::string& text) { return output_target_refusal(text, "", target); }, "",
                       validator_name(target.kind));
  return command.add_option(name, path, help + "; " + output.on_existing)
      ->type_name(target.kind == OutputKind::folder ? "FOLDER" : "FILE")
      ->check(guard);
}

}  // namespace

CLI::Option* add_output_option(CLI::App& command, const std::string& name, std::string& path, const std::string& help,
                               const OutputOption& output) {
  return add(command, name, path, help, output);
}

CLI::Option* add_output_option(CLI::App& command, const std::string& name, std::filesystem::path& path,
                               const std::string& help, const OutputOption& output) {
  return add(command, name, path, help, output);
}

std::optional<OutputKind> output_kind_of(CLI::Option& option) {
  for (const OutputKind kind : {OutputKind::file, OutputKind::image_file, OutputKind::folder}) {
    try {
      option.get_validator(validator_name(kind));
      return kind;
    } catch (const CLI::OptionNotFound&) {}
  }
  return std::nullopt;
}

}  // namespace fovlab::app
