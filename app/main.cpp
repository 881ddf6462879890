// fovlab: psychophysics experiment runner for foveated rendering. This file only wires the
// subcommands together and maps failures to exit codes: 0 success, 2 bad input (one line naming what
// was wrong and what was expected), 1 anything else.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <string>

#include "app/commands.h"
#include "core/input_error.h"

int main(int argc, char** argv) {
  CLI::App app{"fovlab: psychophysics experiments for foveated rendering, on Vulkan"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Help for every subcommand");
  app.set_version_flag("--version", "fovlab " FOVLAB_VERSION);
  fovlab::app::add_commands(app);
  // A first word that is neither a flag nor a subcommand is named as such (CLI11 would say only that
  // a subcommand is required).
  if (argc > 1 && argv[1][0] != '-' &&
      app.get_subcommands([&](CLI::App* command) { return command->get_name() == argv[1]; }).empty()) {
    std::string known;
    for (const CLI::App* command : app.get_subcommands([](CLI::App*) { return true; }))
      known += (known.empty() ? "" : ", ") + command->get_name();
    std::fprintf(stderr, "fovlab: unknown subcommand \"%s\": expected one of %s (fovlab --help)\n", argv[1],
                 known.c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "fovlab: %s\n", e.what());
    return 2;
  } catch (const fovlab::app::CommandExit& e) {
    return e.code;
  } catch (const fovlab::InputError& e) {
    std::fprintf(stderr, "fovlab: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fovlab: internal error: %s\n", e.what());
    return 1;
  }
  return 0;
}
