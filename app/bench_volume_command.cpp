// fovlab bench-volume: Bruder et al. 2019's benchmark on fovlab's volume raycaster (bench/volume_bench.h):
// per volume, random cameras x random gazes, the full and the foveated frame's GPU milliseconds, the
// speed-up per camera summarised as box plots, the share of pixels traced, the reconstruction's
// milliseconds and the foveated frame's SSIM, FLIP and FPSNR against the full one. Prints a Markdown
// table and the command that reproduces it; --json and --svg write the figures and the box plot.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/display_flags.h"
#include "app/foveation_flags.h"  // display_flags_text
#include "app/output_options.h"
#include "bench/volume_bench.h"
#include "core/atomic_file.h"
#include "core/input_error.h"
#include "renderer/vk/context.h"
#include "renderer/volume/volume_raycaster.h"

namespace fovlab::app {

namespace {

struct BenchVolumeOptions {
  std::string scenes = "marschner-lobb,combustion,shepp-logan";
  int width = 512, height = 512;
  int cameras = 8, gazes = 4, frames = 5;
  uint64_t seed = 1;
  double sigma_deg = 2.5;
  bool uncorrected = false;
  DisplayFlags display;
  std::filesystem::path json, svg;
  std::string device;
};

std::string command_line(const BenchVolumeOptions& o) {
  std::ostringstream line;
  line << "fovlab bench-volume --scenes " << o.scenes << " --width " << o.width << " --height " << o.height
       << " --cameras " << o.cameras << " --gazes " << o.gazes << " --frames " << o.frames << " --seed " << o.seed
       << " --sigma-deg " << o.sigma_deg << (o.uncorrected ? " --no-opacity-correction " : " ")
       << display_flags_text(o.display);
  return line.str();
}

void run_bench_volume(BenchVolumeOptions options) {
  if (options.width < 1 || options.width > kMaxVolumeFrameSidePx || options.height < 1 ||
      options.height > kMaxVolumeFrameSidePx)
    throw InputError("--width, --height: expected 1 to " + std::to_string(kMaxVolumeFrameSidePx) + " pixels");
  if (options.cameras < 1 || options.cameras > 100000) throw InputError("--cameras: expected 1 to 100000");
  if (options.gazes < 1 || options.gazes > 100000) throw InputError("--gazes: expected 1 to 100000");
  if (options.frames < 1 || options.frames > 1000) throw InputError("--frames: expected 1 to 1000");
  if (!(options.sigma_deg > 0.0 && options.sigma_deg <= 90.0))
    throw InputError("--sigma-deg: expected a radius in degrees in (0, 90]");
  if (!options.display.gaze.empty()) throw InputError("--gaze: the benchmark draws its own gazes (--gazes, --seed)");
  default_to_fpt_study_display(options.display);
  bench::VolumeBenchPlan plan;
  std::stringstream names(options.scenes);
  for (std::string name; std::getline(names, name, ',');)
    if (!name.empty()) plan.scenes.push_back(name);
  if (plan.scenes.empty()) throw InputError("--scenes: expected one or more volume scenes, comma-separated");
  plan.width_px = options.width;
  plan.height_px = options.height;
  plan.cameras = options.cameras;
  plan.gazes = options.gazes;
  plan.frames = options.frames;
  plan.seed = options.seed;
  plan.sigma_deg = options.sigma_deg;
  plan.correct_opacity = !options.uncorrected;
  plan.display = parse_display(options.display, options.width, options.height);
  plan.voronoi_cache = kVoronoiCacheFolder.string();

  vk::Context context(context_options(options.device));
  const auto results = bench::run_volume_bench(
      context, plan, [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); });
  fail_on_validation_messages(context);
  std::printf("%s\n%s, GPU ms medians of %d frames a configuration, %d cameras x %d gazes a volume, on %s\n\n%s",
              command_line(options).c_str(), "foveated against full volume raycasting", options.frames, options.cameras,
              options.gazes, context.description.name.c_str(), bench::volume_bench_markdown(results).c_str());
  if (!options.json.empty()) {
    nlohmann::json json = bench::volume_bench_json(plan, results);
    json["command"] = command_line(options);
    json["device"] = context.description.name;
    write_text_atomically(options.json, json.dump(2) + "\n");
  }
  if (!options.svg.empty()) write_text_atomically(options.svg, bench::volume_bench_svg(results));
}

}  // namespace

void add_bench_volume_command(CLI::App& app) {
  auto options = std::make_shared<BenchVolumeOptions>();
  CLI::App* command = app.add_subcommand(
      "bench-volume",
      "Bruder et al. 2019's benchmark: full against Voronoi-foveated volume raycasting over random cameras and gazes");
  command->add_option("--scenes", options->scenes, "Volume scenes, comma-separated (built-in names or .toml files)");
  command->add_option("--width", options->width, "Frame width in pixels (512)");
  command->add_option("--height", options->height, "Frame height in pixels (512)");
  command->add_option("--cameras", options->cameras, "Random cameras a volume (the paper: 256)");
  command->add_option("--gazes", options->gazes, "Random gazes a camera (the paper: 256)");
  command->add_option("--frames", options->frames, "Timed frames a configuration, after one untimed (the paper: 5)");
  command->add_option("--seed", options->seed, "Seed of the cameras and gazes");
  command->add_option("--sigma-deg", options->sigma_deg, "Radius s of the sampling density's Gaussian, degrees (2.5)");
  command->add_flag("--no-opacity-correction", options->uncorrected, "The authors' uncorrected peripheral opacity");
  add_display_flags(*command, options->display, false);
  add_output_option(*command, "--json", options->json, "Every figure as JSON", {{OutputKind::file}, kReplacesAFile});
  add_output_option(*command, "--svg", options->svg, "The speed-ups' box plot (SVG)",
                    {{OutputKind::file}, kReplacesAFile});
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  command->callback([options] { run_bench_volume(*options); });
}

}  // namespace fovlab::app
