#include "app/cli_support.h"

#include <stdexcept>

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

}  // namespace fovlab::app
