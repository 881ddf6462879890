// fovlab bench-present: the time from reading a gaze sample to the present of the frame rendered
// with it, for a FIPR stimulus, as a session spends it on every refresh (SessionRun::
// present_stimulus): the sample is read, the FIPR image is rendered with it and sRGB-encoded on the
// rendering device (StimulusLibrary::frame), handed to the presenter and presented; then the frame
// is read back and hashed for the log (StimulusLibrary::hash), after the present. Timed on the
// steady clock from the read to present()'s return (the window's "after_queue_present" time, which
// the log records). Rows by the frame's path to the swapchain:
// - window, on_device: one device renders and presents (a session's default): no host round trip;
// - window, via_host: the renderer on a device of its own, the window on another (fovlab run
//   --present-device): the frame is read back and uploaded on every refresh, as every session did
//   before presentation moved to the rendering device;
// - headless: the same render and hash without a display (its present is free).
// Prints a Markdown table; --json writes every figure.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/statistics/percentile.h"
#include "app/cli_support.h"
#include "app/commands.h"
#include "app/output_options.h"
#include "core/atomic_file.h"
#include "core/input_error.h"
#include "protocols/gaze/gaze_sample.h"
#include "protocols/gaze/synthetic_gaze_source.h"
#include "display/headless_presenter.h"
#include "display/window_presenter.h"
#include "protocols/stimuli/stimulus_library.h"
#include "protocols/stimuli/stimulus_settings.h"

namespace fovlab::app {

namespace {

constexpr int kWarmupRefreshes = 5;  // rendered and presented before the timed ones (pipelines, caches)

struct BenchPresentOptions {
  std::vector<std::string> sizes = {"320x180", "1280x720"};
  int width = 0;  // --width/--height: one size instead of --sizes
  int height = 0;
  int refreshes = 120;
  std::string presenter = "both";  // window, headless, both
  std::string scene = "primitives";
  std::filesystem::path json;
  std::string device;
};

struct Size {
  int width = 0;
  int height = 0;
};

Size parse_size(const std::string& text) {
  const size_t x = text.find('x');
  Size size;
  try {
    size_t end_w = 0, end_h = 0;
    if (x == std::string::npos) throw std::invalid_argument("no x");
    size.width = std::stoi(text.substr(0, x), &end_w);
    size.height = std::stoi(text.substr(x + 1), &end_h);
    if (end_w != x || end_h != text.size() - x - 1) throw std::invalid_argument("trailing text");
  } catch (const std::exception&) {
    size = {};
  }
  if (size.width < 16 || size.height < 16 || size.width > 4096 || size.height > 4096)
    throw InputError("--sizes: expected WxH with 16 to 4096 pixels a side (e.g. 320x180), got \"" + text + "\"");
  return size;
}

// A FIPR stimulus of the given size with the method's defaults, on a 600 mm wide display seen from
// 600 mm, one animation frame a refresh at 60 frames a second.
StimulusSpec fipr_spec(const std::string& scene, Size size, int images) {
  StimulusSpec spec;
  spec.scene = scene;
  spec.parameters = default_parameters(RenderMethod::foveated_pyramid);
  std::get<FoveatedPyramidParameters>(spec.parameters).display = {600.0, 600.0 * size.height / size.width, 600.0};
  spec.width_px = size.width;
  spec.height_px = size.height;
  spec.frame_count = images;
  spec.frames_per_second = 60.0;
  spec.camera_start_s = 0.5;
  return spec;
}

struct Row {
  std::string presenter;   // "window", "headless"
  std::string frame_path;  // "on_device", "via_host", "none"
  std::string presenter_device;
  std::string present_clock;
  Size size;
  std::vector<double> latency_s, render_s, present_s, hash_s;
  int dropped_frames = 0;  // refresh periods missed between presents (the presenter's clock)
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// One presenter and size: warm-up refreshes, then `refreshes` timed ones, each with a fresh gaze
// sample from a synthetic fixation pattern read on the presenter's clock.
Row measure(Presenter& presenter, StimulusLibrary& library, int id, const StimulusSpec& spec, int refreshes) {
  Row row;
  row.size = {spec.width_px, spec.height_px};
  row.present_clock = presenter.present_clock();
  SyntheticGazeParams gaze_params;
  gaze_params.seed = 1;
  SyntheticGazeSource gaze(gaze_params, spec.width_px, spec.height_px);
  std::optional<GazeSample> last_valid;
  double previous_present_s = -1.0;
  for (int image = 0; image < kWarmupRefreshes + refreshes; ++image) {
    const auto read_at = std::chrono::steady_clock::now();
    const GazeSample sample = sanitize_gaze(gaze.sample(presenter.now_s()), spec.width_px, spec.height_px,
                                            last_valid ? &*last_valid : nullptr);
    if (sample.valid) last_valid = sample;
    const PreparedFrame& frame = library.frame(id, spec, StimulusImage{image, image, sample});
    const double render_s = seconds_since(read_at);
    const double shown_s = frame.on_device ? presenter.present(frame.on_device) : presenter.present(frame.image);
    const double latency_s = seconds_since(read_at);
    const auto hash_start = std::chrono::steady_clock::now();
    library.hash(frame);  // after the present, as a session does
    const double hash_s = seconds_since(hash_start);
    if (image < kWarmupRefreshes) continue;
    if (previous_present_s >= 0) {
      const long periods = std::lround((shown_s - previous_present_s) * presenter.refresh_hz());
      if (periods > 1) row.dropped_frames += static_cast<int>(periods - 1);
    }
    previous_present_s = shown_s;
    row.latency_s.push_back(latency_s);
    row.render_s.push_back(render_s);
    row.present_s.push_back(latency_s - render_s);
    row.hash_s.push_back(hash_s);
  }
  return row;
}

double median_ms(const std::vector<double>& seconds) {
  return 1e3 * analysis::nearest_rank_percentile(seconds, 50.0).value_or(NAN);
}
double p95_ms(const std::vector<double>& seconds) {
  return 1e3 * analysis::nearest_rank_percentile(seconds, 95.0).value_or(NAN);
}

std::string command_line(const BenchPresentOptions& o, const std::vector<Size>& sizes) {
  std::string text = "fovlab bench-present --sizes ";
  for (size_t i = 0; i < sizes.size(); ++i)
    text += (i ? "," : "") + std::to_string(sizes[i].width) + "x" + std::to_string(sizes[i].height);
  text += " --refreshes " + std::to_string(o.refreshes) + " --presenter " + o.presenter + " --scene " + o.scene;
  if (!o.device.empty()) text += " --device " + o.device;
  return text;
}

void run_bench_present(const BenchPresentOptions& options) {
  std::vector<Size> sizes;
  if (options.width != 0 || options.height != 0) {
    sizes.push_back(parse_size(std::to_string(options.width) + "x" + std::to_string(options.height)));
  } else {
    for (const std::string& text : options.sizes) sizes.push_back(parse_size(text));
  }
  if (sizes.empty()) throw InputError("--sizes: expected at least one WxH");
  if (options.refreshes < 1 || options.refreshes > 100000)
    throw InputError("--refreshes " + std::to_string(options.refreshes) + ": expected 1 to 100000");
  if (options.presenter != "window" && options.presenter != "headless" && options.presenter != "both")
    throw InputError("--presenter " + options.presenter + ": expected window, headless or both");
  const bool want_window = options.presenter != "headless";
  if (want_window && !display_available())
    throw InputError(
        "bench-present: no display for the window presenter (DISPLAY is not set); run it under Xvfb "
        "(xvfb-run -a -s -noreset fovlab bench-present ...) or with --presenter headless");
  const std::filesystem::path json_folder = options.json.parent_path();
  if (!options.json.empty() && !json_folder.empty() && !std::filesystem::is_directory(json_folder))
    throw InputError("--json " + options.json.string() + ": expected a file in an existing folder");

  const vk::ContextOptions context_settings = context_options(options.device);
  vk::Context context(context_settings);
  StimulusLibrary library(context);
  std::vector<Row> rows;
  int id = 0;
  for (const Size& size : sizes) {
    const StimulusSpec spec = fipr_spec(options.scene, size, kWarmupRefreshes + options.refreshes);
    library.prepare({{id, spec}});  // the scene's compilation and the settings' checks, untimed
    if (want_window) {
      WindowPresenterOptions window;
      window.width_px = size.width;
      window.height_px = size.height;
      window.title = "fovlab bench-present";
      window.screenshots = false;  // as in a session without --screenshots
      window.validation = context_settings.validation;
      window.device_selector = context_settings.device_selector;
      for (const bool on_device : {true, false}) {
        WindowPresenter presenter(window);
        // on_device: a library on the window's own device; via_host: the one on `context`.
        std::optional<StimulusLibrary> window_library;
        if (on_device) {
          window_library.emplace(presenter.context());
          window_library->prepare({{id, spec}});
        }
        Row row = measure(presenter, on_device ? *window_library : library, id, spec, options.refreshes);
        row.presenter = "window";
        row.frame_path = on_device ? "on_device" : "via_host";
        row.presenter_device = presenter.device_name();
        if (presenter.validation_message_count() > 0)
          throw std::runtime_error("the Vulkan validation layer reported " +
                                   std::to_string(presenter.validation_message_count()) +
                                   " message(s) in the window (see stderr)");
        rows.push_back(std::move(row));
      }
    }
    if (options.presenter != "window") {
      HeadlessPresenter presenter(60.0);
      Row row = measure(presenter, library, id, spec, options.refreshes);
      row.presenter = "headless";
      row.frame_path = "none";
      row.presenter_device = "none";
      rows.push_back(std::move(row));
    }
    ++id;
  }
  fail_on_validation_messages(context);

  nlohmann::json report = {{"command", command_line(options, sizes)},
                           {"render_device", context.description.name},
                           {"stimulus", {{"method", "fipr"}, {"scene", options.scene}}},
                           {"refreshes", options.refreshes},
                           {"warmup_refreshes", kWarmupRefreshes},
                           {"percentiles", "nearest rank"},
                           {"rows", nlohmann::json::array()}};
  std::string table =
      "| presenter | frame path | size | gaze to present, median ms | p95 ms | render, median ms | present, median ms "
      "| "
      "read-back + hash after the present, median ms | dropped frames | present clock |\n"
      "|---|---|---|---:|---:|---:|---:|---:|---:|---|\n";
  char line[512];
  for (const Row& row : rows) {
    report["rows"].push_back({{"presenter", row.presenter},
                              {"frame_path", row.frame_path},
                              {"presenter_device", row.presenter_device},
                              {"present_clock", row.present_clock},
                              {"width", row.size.width},
                              {"height", row.size.height},
                              {"refreshes", row.latency_s.size()},
                              {"median_ms", median_ms(row.latency_s)},
                              {"p95_ms", p95_ms(row.latency_s)},
                              {"render_median_ms", median_ms(row.render_s)},
                              {"present_median_ms", median_ms(row.present_s)},
                              {"hash_median_ms", median_ms(row.hash_s)},
                              {"dropped_frames", row.dropped_frames}});
    std::snprintf(line, sizeof line, "| %s | %s | %dx%d | %.2f | %.2f | %.2f | %.2f | %.2f | %d | %s |\n",
                  row.presenter.c_str(), row.frame_path.c_str(), row.size.width, row.size.height,
                  median_ms(row.latency_s), p95_ms(row.latency_s), median_ms(row.render_s), median_ms(row.present_s),
                  median_ms(row.hash_s), row.dropped_frames, row.present_clock.c_str());
    table += line;
  }
  std::printf(
      "# fovlab bench-present\n\nCommand: `%s`\n\nRender device: %s; FIPR on %s; %d timed refreshes after %d "
      "warm-up ones; nearest-rank percentiles.\n\n%s",
      report["command"].get<std::string>().c_str(), context.description.name.c_str(), options.scene.c_str(),
      options.refreshes, kWarmupRefreshes, table.c_str());
  if (!options.json.empty()) write_text_atomically(options.json, report.dump(2) + "\n");
}

}  // namespace

void add_bench_present_command(CLI::App& app) {
  auto options = std::make_shared<BenchPresentOptions>();
  CLI::App* command = app.add_subcommand(
      "bench-present", "Time gaze sample to present for a FIPR stimulus, window and headless presenter");
  command->add_option("--sizes", options->sizes, "Stimulus sizes, WxH, comma-separated (320x180,1280x720)")
      ->delimiter(',');
  command->add_option("--width", options->width, "One stimulus width instead of --sizes (with --height)");
  command->add_option("--height", options->height, "One stimulus height instead of --sizes (with --width)");
  command->add_option("--refreshes", options->refreshes, "Timed refreshes a row (120)");
  command->add_option(
      "--presenter", options->presenter,
      "window, headless or both (both; the window needs a display: xvfb-run -a -s -noreset without one)");
  command->add_option("--scene", options->scene, "Sphere-traced scene of the FIPR stimulus (primitives)");
  add_output_option(*command, "--json", options->json, "Write every figure as JSON",
                    {{OutputKind::file}, kReplacesAFile});
  command->add_option("--device", options->device, "Vulkan device for rendering: index or part of its name");
  command->callback([options] { run_bench_present(*options); });
}

}  // namespace fovlab::app
