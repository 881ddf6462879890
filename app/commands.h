#pragma once
// Each subcommand registers its flags and its action on the CLI11 app. The action runs after
// parsing; InputError from it becomes exit code 2 (app/main.cpp).
#include <CLI/CLI.hpp>

namespace fovlab::app {

// Every subcommand below, in the order --help lists them (app/commands.cpp): the whole command line,
// which main() parses and the tests read (SessionRace.EveryOptionThatLooksLikeAnOutputIsRegisteredAsOne,
// tests/protocols/session/session_race_test.cpp).
void add_commands(CLI::App& app);

void add_render_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_bench_merge_command(CLI::App& app);
void add_bench_fpt_command(CLI::App& app);
void add_bench_present_command(CLI::App& app);
void add_devices_command(CLI::App& app);
void add_methods_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_validate_command(CLI::App& app);
void add_replay_command(CLI::App& app);
void add_export_command(CLI::App& app);
void add_analyze_command(CLI::App& app);
void add_rays_command(CLI::App& app);
void add_upsample_command(CLI::App& app);
void add_blend_command(CLI::App& app);
void add_resample_command(CLI::App& app);
void add_voronoi_command(CLI::App& app);
void add_bench_volume_command(CLI::App& app);
void add_prerender_command(CLI::App& app);
void add_slurm_command(CLI::App& app);  // slurm prerender, slurm bench
void add_binomial_command(CLI::App& app);
void add_simulate_command(CLI::App& app);  // and bench-quest

// Thrown by a command that finished but must report failure with this exit code (replay --verify
// found differences: 1).
struct CommandExit {
  int code = 1;
};

}  // namespace fovlab::app
