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
#include "core/atomic_file.h"
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
  // One sweep, or with --headset one an eye (left first). Both eyes: each eye's images, tables and
  // charts in --out-dir's left/ and right/, and --json holds {"eyes": [the left's, the right's]}.
  std::vector<bench::BenchOptions> eyes = read_bench_flags_per_eye(flags);
  const bool both_eyes = eyes.size() > 1;
  std::vector<bench::BenchPlan> plans;
  std::vector<std::vector<SceneSource>> scenes;  // each eye's, all checked before anything is measured
  for (bench::BenchOptions& options : eyes) {
    const std::filesystem::path out_dir =
        both_eyes && !flags.out_dir.empty() ? flags.out_dir / options.eye_name : flags.out_dir;
    options.out_dir = out_dir;
    options.write_frame_images = [out_dir](const std::string& stem, const SphereTraceResult& frame,
                                           const SphereTraceSettings& settings) {
      write_frame_images(out_dir, stem, frame, settings);
    };
    plans.push_back(bench::plan_bench(std::move(options)));
    scenes.push_back(bench::load_bench_scenes(plans.back()));
  }
  if (!flags.out_dir.empty()) create_output_folder(flags.out_dir, "--out-dir");
  nlohmann::json per_eye = nlohmann::json::array();
  for (size_t index = 0; index < plans.size(); ++index) {
    const bench::BenchPlan& plan = plans[index];
    if (both_eyes && !plan.options.out_dir.empty()) std::filesystem::create_directories(plan.options.out_dir);
    const bench::BenchReport report =
        bench::run_bench(plan, scenes[index], step_progress("bench", bench::units_measured(plan)));
    if (report.part) {  // a part's Pareto fronts and tables are the whole sweep's, made by bench-merge
      bench::write_bench_part(report, flags.json);
      return;
    }
    nlohmann::json json = bench::bench_report_json(report);
    bench::finish_sweep(json, true, both_eyes ? std::filesystem::path() : flags.json, plan.options.out_dir);
    per_eye.push_back(std::move(json));
  }
  if (both_eyes && !flags.json.empty())
    write_text_atomically(flags.json, nlohmann::json{{"eyes", per_eye}}.dump(2) + "\n");
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
