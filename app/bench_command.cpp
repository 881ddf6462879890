// fovlab bench: ground truth against the inverted pyramid (IPR), its foveated form (FIPR,
// Polychronakis et al. 2023) and Ye et al. 2022's sampling models (rmfr, hyperbolic, linear, kfr),
// scene by scene and spp by spp (and, for FIPR, periphery refresh by fovea): median GPU
// milliseconds, speed-up, GT's and IPR's time over the one-step floor, steps per pixel, and SSIM,
// PSNR, FLIP and FPSNR against GT; where the time goes; the trade-off between speed and error as
// charts with their Pareto fronts.
//
// The benchmark is the library bench/ (bench/bench.h); this file reads the flags
// (app/bench_flags.h), runs the sweep, or with --cells I/N one part of it, and writes its images.
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "app/bench_flags.h"
#include "app/cli_support.h"
#include "app/commands.h"
#include "app/output_options.h"
#include "app/render_outputs.h"
#include "bench/bench.h"
#include "core/image_io.h"

namespace fovlab::app {

namespace {

void write_frame_images(const std::filesystem::path& out_dir, const std::string& stem, const SphereTraceResult& frame,
                        const SphereTraceSettings& settings) {
  write_colour(out_dir / (stem + ".png"), frame.colour_linear);
  write_step_heatmap(out_dir / (stem + "_steps.png"), frame, settings);
  if (settings.method == TraceMethod::foveated_pyramid) write_image(out_dir / (stem + "_mask.png"), frame.mask);
  if (settings.sampling) write_image(out_dir / (stem + "_samples.png"), samples_per_pixel_image(frame.mask));
}

void run_bench(const BenchFlags& flags) {
  bench::BenchOptions options = read_bench_flags(flags);
  options.write_frame_images = [out_dir = flags.out_dir](const std::string& stem, const SphereTraceResult& frame,
                                                         const SphereTraceSettings& settings) {
    write_frame_images(out_dir, stem, frame, settings);
  };
  const bench::BenchPlan plan = bench::plan_bench(std::move(options));
  const std::vector<SceneSource> scenes = bench::load_bench_scenes(plan);
  if (!flags.out_dir.empty()) create_output_folder(flags.out_dir, "--out-dir");
  const bench::BenchReport report = bench::run_bench(plan, scenes, step_progress("bench", bench::units_measured(plan)));
  if (report.part) {  // a part's Pareto fronts and tables are the whole sweep's, made by bench-merge
    bench::write_bench_part(report, flags.json);
    return;
  }
  nlohmann::json json = bench::bench_report_json(report);
  bench::finish_sweep(json, true, flags.json, flags.out_dir);
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto flags = std::make_shared<BenchFlags>();
  CLI::App* command = app.add_subcommand(
      "bench",
      "Benchmark GT against IPR, FIPR and the sampling models: time, steps, SSIM, PSNR, FLIP, FPSNR, Pareto fronts");
  add_bench_flags(*command, *flags);
  command->callback([flags, command] {
    note_given_bench_flags(*command, *flags);
    run_bench(*flags);
  });
}

}  // namespace fovlab::app
