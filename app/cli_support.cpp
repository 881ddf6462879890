#include "app/cli_support.h"

#include <map>
#include <stdexcept>

#include "core/input_error.h"

namespace fovlab::app {

vk::ContextOptions context_options(const std::string& device_selector) {
  return {device_selector, vk::validation_requested_by_default()};
}

void fail_on_validation_messages(const vk::Context& context) {
  if (context.validation_message_count() > 0) {
    throw std::runtime_error(std::to_string(context.validation_message_count()) +
                             " Vulkan validation message(s); see above");
  }
}

void add_trace_options(CLI::App& command, SphereTraceSettings& settings) {
  command.add_option("--time", settings.time_s, "Scene time in seconds (camera path, moving lights)");
  command.add_option("--levels", settings.pyramid_levels, "IPR pyramid levels, 2 to 5 (3: 1/16, 1/4, full)");
  command.add_option("--min-filter", settings.min_filter_size, "IPR min-filter size: 1, 3 or 5");
  command.add_option("--max-steps", settings.max_steps, "Step cap of one ray at one level");
  command.add_option("--hit-threshold", settings.hit_threshold,
                     "Hit when distance < t x pixel angle x this (pixel-footprint epsilon)");
}

void validate_trace_flags(const SphereTraceSettings& settings) {
  static const std::map<std::string, std::string> flag_of_field = {
      {"width", "--width"},
      {"height", "--height"},
      {"samples_per_pixel", "--spp"},
      {kSamplesPerFrameField, "--width x --height x --spp"},
      {"pyramid_levels", "--levels"},
      {"min_filter_size", "--min-filter"},
      {"max_steps", "--max-steps"},
      {"hit_threshold", "--hit-threshold"},
      {"time_s", "--time"},
      {"fovea_deg", "--fovea-deg"},
      {"outer_periphery_deg", "--outer-periphery-deg"},
      {"periphery_refresh", "--refresh"},
      {"periphery_steps", "--periphery-steps"},
      {"edge_threshold", "--edge-threshold"}};
  try {
    validate(settings);
  } catch (const SettingError& error) {
    const auto flag = flag_of_field.find(error.field);
    if (flag == flag_of_field.end()) throw;
    throw InputError(flag->second + error.detail);
  }
}

}  // namespace fovlab::app
