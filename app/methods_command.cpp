// fovlab methods: the rendering methods a study's [stimulus.reference] and [stimulus.test] may use,
// with every parameter's key, unit, default and allowed values, made from the method descriptors
// (study/stimulus/render_method.h). docs/config.md carries the same table (a test keeps it so).
#include <cstdio>

#include "app/commands.h"
#include "study/stimulus/render_method.h"

namespace fovlab::app {

void add_methods_command(CLI::App& app) {
  CLI::App* command =
      app.add_subcommand("methods", "List the rendering methods and their parameters (Markdown, as in docs/config.md)");
  command->callback([] { std::fputs(methods_markdown().c_str(), stdout); });
}

}  // namespace fovlab::app
