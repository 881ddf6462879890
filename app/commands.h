#pragma once
// Each subcommand registers its flags and its action on the CLI11 app. The action runs after
// parsing; InputError from it becomes exit code 2 (app/main.cpp).
#include <CLI/CLI.hpp>

namespace fovlab::app {

void add_render_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_devices_command(CLI::App& app);

}  // namespace fovlab::app
