#include "app/commands.h"

namespace fovlab::app {

void add_commands(CLI::App& app) {
  add_render_command(app);
  add_compare_command(app);
  add_bench_command(app);
  add_bench_merge_command(app);
  add_bench_fpt_command(app);
  add_bench_present_command(app);
  add_devices_command(app);
  add_methods_command(app);
  add_run_command(app);
  add_validate_command(app);
  add_replay_command(app);
  add_export_command(app);
  add_analyze_command(app);
  add_rays_command(app);
  add_upsample_command(app);
  add_blend_command(app);
  add_resample_command(app);
  add_voronoi_command(app);
  add_bench_volume_command(app);
  add_prerender_command(app);
  add_slurm_command(app);
  add_binomial_command(app);
  add_simulate_command(app);
}

}  // namespace fovlab::app
