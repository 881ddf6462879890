// fovlab devices: the Vulkan devices this machine has, and which one fovlab picks by default.
#include <cstdio>

#include "app/commands.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

void add_devices_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand("devices", "List Vulkan devices (index, name, type)");
  command->callback([] {
    for (const vk::DeviceDescription& d : vk::list_devices()) {
      std::printf("%u  %-40s %-15s Vulkan %-9s %s%s\n", d.index, d.name.c_str(), d.type.c_str(), d.api_version.c_str(),
                  d.driver.c_str(), d.usable ? "" : ("  [unusable: " + d.unusable_reason + "]").c_str());
    }
    vk::Context context({"", false});
    std::printf("default: %u %s\n", context.description.index, context.description.name.c_str());
  });
}

}  // namespace fovlab::app
