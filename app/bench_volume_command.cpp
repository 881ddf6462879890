// fovlab bench-volume: Bruder et al. 2019's benchmark on fovlab's volume raycaster (bench/volume_bench.h):
// per volume, random cameras x random gazes, the full and the foveated frame's GPU milliseconds, the
// speed-up per camera summarised as box plots, the share of pixels traced, the reconstruction's
// milliseconds and the foveated frame's SSIM, FLIP and FPSNR against the full one, the fovea's size in
// pixels, the sites on the screen and the rays traced. The frame may be centred on a larger display
// at its pixel pitch (--display-px; --bruder-2019-display: the paper's screen). Prints a Markdown
// table and the command that reproduces it; --json and --svg write the figures and the box plot.
#include <charconv>
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
#include "foveation/voronoi_mask.h"
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
  bool global_reach = false;
  bool paper_display = false;
  std::string display_px;  // --display-px WxH: the display's pixels ("": the frame is the display)
  DisplayFlags display;
  std::filesystem::path json, svg;
  std::string device;
};

std::string command_line(const BenchVolumeOptions& o) {
  std::ostringstream line;
  line << "fovlab bench-volume --scenes " << o.scenes << " --width " << o.width << " --height " << o.height
       << " --cameras " << o.cameras << " --gazes " << o.gazes << " --frames " << o.frames << " --seed " << o.seed
       << " --sigma-deg " << o.sigma_deg << (o.uncorrected ? " --no-opacity-correction " : " ")
       << (o.global_reach ? "--global-reach " : "");
  if (o.paper_display) {
    line << "--bruder-2019-display";
    if (!o.display.distance_mm.empty()) line << " --distance-mm " << o.display.distance_mm;
  } else {
    line << display_flags_text(o.display);
    if (!o.display_px.empty()) line << " --display-px " << o.display_px;
  }
  return line.str();
}

// Bruder et al. 2019's set-up (section 5): a 1024x1024 frame on a 24-inch 1920x1080 screen. The paper
// gives no viewing distance: 600 mm is assumed (--distance-mm overrides it).
constexpr const char* kBruderDiagonalIn = "24";
constexpr const char* kBruderDisplayPx = "1920x1080";
constexpr const char* kBruderDistanceMm = "600";

// --display-px WxH: two whole numbers of pixels, 1 to 16384 each.
std::pair<int, int> parse_display_px(const std::string& text) {
  const std::string expected = "WxH, the display's pixels, two whole numbers from 1 to 16384 (e.g. 1920x1080)";
  const auto parts = split_pair(text, "xX");
  if (!parts) fail_flag("--display-px", expected, text);
  const auto whole = [&](std::string_view part) {
    int value = 0;
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (error != std::errc() || end != part.data() + part.size() || value < 1 || value > 16384)
      fail_flag("--display-px", expected, text);
    return value;
  };
  return {whole(parts->first), whole(parts->second)};
}

// Where the frame sits: "frame 512x512 px (141.7x141.7 mm) at the centre of a 1920x1080 px, 531.3x298.9 mm
// display at 600 mm; 37.8 px/deg at the centre, fovea s = 2.5 deg = 94.6 px".
std::string frame_line(const bench::VolumeBenchPlan& plan) {
  char text[320];
  std::snprintf(text, sizeof text,
                "frame %dx%d px (%.1fx%.1f mm) at the centre of a %dx%d px, %.1fx%.1f mm display at %g mm; %.1f "
                "px/deg at the centre, fovea s = %g deg = %.1f px",
                plan.display.width_px, plan.display.height_px, plan.display.width_mm, plan.display.height_mm,
                plan.screen.width_px, plan.screen.height_px, plan.screen.width_mm, plan.screen.height_mm,
                plan.screen.viewing_distance_mm, plan.display.pixels_per_degree_at_centre(), plan.sigma_deg,
                density_sigma_px(plan.display, plan.sigma_deg));
  return text;
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
  if (options.paper_display) {
    if (!options.display.diagonal_in.empty() || !options.display.size_mm.empty() || !options.display_px.empty())
      throw InputError(std::string(!options.display.diagonal_in.empty() ? "--diagonal-in"
                                   : !options.display.size_mm.empty()   ? "--size-mm"
                                                                         : "--display-px") +
                       ": --bruder-2019-display sets the display (24 inches, 1920x1080 px); only --distance-mm "
                       "may be given with it");
    options.display.diagonal_in = kBruderDiagonalIn;
    options.display_px = kBruderDisplayPx;
    if (options.display.distance_mm.empty()) options.display.distance_mm = kBruderDistanceMm;
  }
  const auto [display_width_px, display_height_px] =
      options.display_px.empty() ? std::pair<int, int>{options.width, options.height}
                                 : parse_display_px(options.display_px);
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
  plan.trace_read_sites_only = !options.global_reach;
  plan.screen = parse_display(options.display, display_width_px, display_height_px);
  plan.display = bench::frame_on_display(plan.screen, options.width, options.height);
  plan.voronoi_cache = kVoronoiCacheFolder.string();

  vk::Context context(context_options(options.device));
  const auto results = bench::run_volume_bench(
      context, plan, [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); });
  fail_on_validation_messages(context);
  std::printf("%s\n%s, GPU ms medians of %d frames a configuration, %d cameras x %d gazes a volume, on %s\n%s\n\n%s",
              command_line(options).c_str(), "foveated against full volume raycasting", options.frames, options.cameras,
              options.gazes, context.description.name.c_str(), frame_line(plan).c_str(),
              bench::volume_bench_markdown(results).c_str());
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
  command->add_flag("--global-reach", options->global_reach,
                    "Trace every site within the mask's one neighbour reach of the screen (the earlier rule; the "
                    "same frames, more rays)");
  add_display_flags(*command, options->display, false);
  command->add_option("--display-px", options->display_px,
                      "The display's pixels WxH (e.g. 1920x1080): --diagonal-in/--size-mm are the display's, and "
                      "the frame is centred on it at its pixel pitch (default: the frame is the display)");
  command->add_flag("--bruder-2019-display", options->paper_display,
                    "Bruder et al. 2019's screen: 24 inches, 1920x1080 px, at 600 mm (assumed; the paper gives no "
                    "distance); use with --width 1024 --height 1024 for the paper's frame");
  add_output_option(*command, "--json", options->json, "Every figure as JSON", {{OutputKind::file}, kReplacesAFile});
  add_output_option(*command, "--svg", options->svg, "The speed-ups' box plot (SVG)",
                    {{OutputKind::file}, kReplacesAFile});
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  command->callback([options] { run_bench_volume(*options); });
}

}  // namespace fovlab::app
