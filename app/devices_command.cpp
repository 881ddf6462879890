// fovlab devices: the Vulkan devices this machine has, which one fovlab picks by default, and the
// active OpenXR runtime, if any.
#include <cstdio>

#include "app/commands.h"
#include "display/openxr/openxr_runtime_info.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

void add_devices_command(CLI::App& app) {
  CLI::App* command =
      app.add_subcommand("devices", "List Vulkan devices (index, name, type) and the active OpenXR runtime");
  command->callback([] {
    for (const vk::DeviceDescription& d : vk::list_devices()) {
      std::printf("%u  %-40s %-15s Vulkan %-9s %s%s\n", d.index, d.name.c_str(), d.type.c_str(), d.api_version.c_str(),
                  d.driver.c_str(), d.usable ? "" : ("  [unusable: " + d.unusable_reason + "]").c_str());
    }
    vk::Context context({"", false});
    std::printf("default: %u %s\n", context.description.index, context.description.name.c_str());
    for (const std::string& line : describe_openxr_runtime(query_openxr_runtime())) std::printf("%s\n", line.c_str());
  });
}

}  // namespace fovlab::app
