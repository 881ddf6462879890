// fovlab bench: ground truth against the inverted pyramid, scene by scene and spp by spp: median GPU
// milliseconds, speed-up, steps per pixel, SSIM and PSNR against GT, and where the time goes.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "analysis/image_metrics/image_metrics.h"
#include "app/cli_support.h"
#include "app/commands.h"
#include "app/render_outputs.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

namespace {

struct BenchOptions {
  std::vector<std::string> scenes{"primitives", "columns", "temple"};
  std::vector<int> spps{1, 4, 16};
  SphereTraceSettings settings;
  int repeats = 5;
  std::filesystem::path json;
  std::filesystem::path out_dir;
  std::string device;
};

template <typename T>
std::string join(const std::vector<T>& values) {
  std::ostringstream out;
  for (size_t i = 0; i < values.size(); ++i) out << (i ? "," : "") << values[i];
  return out.str();
}

// The command that reproduces these numbers, every setting spelled out.
std::string reproducing_command(const BenchOptions& options) {
  const SphereTraceSettings& s = options.settings;
  std::ostringstream out;
  out << "fovlab bench --scenes " << join(options.scenes) << " --spp " << join(options.spps) << " --width " << s.width
      << " --height " << s.height << " --repeats " << options.repeats << " --time " << s.time_s << " --levels "
      << s.pyramid_levels << " --min-filter " << s.min_filter_size << " --max-steps " << s.max_steps
      << " --hit-threshold " << s.hit_threshold;
  return out.str();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// Timings of one method over the repeats, plus the (deterministic) frame of its first run.
struct MethodRuns {
  SphereTraceResult frame;
  std::vector<double> gpu_ms;
  std::vector<double> wall_ms;
  std::map<std::string, std::vector<double>> pass_ms;

  void add(const SphereTraceResult& result, double wall) {
    gpu_ms.push_back(result.gpu_ms);
    wall_ms.push_back(wall);
    for (const vk::PassTime& pass : result.passes) pass_ms[pass.name].push_back(pass.gpu_ms);
  }

  nlohmann::json json(const SphereTraceSettings& settings) const {
    nlohmann::json passes = nlohmann::json::object();
    for (const auto& [name, values] : pass_ms) passes[name] = median(values);
    return {{"median_gpu_ms", median(gpu_ms)},
            {"median_wall_ms", median(wall_ms)},
            {"gpu_ms_runs", gpu_ms},
            {"median_pass_gpu_ms", passes},
            {"total_steps", frame.total_steps},
            {"steps_per_pixel", frame.mean_steps_per_pixel()},
            {"steps_per_sample", frame.mean_steps_per_pixel() / settings.samples_per_pixel},
            {"capped_rays", frame.capped_rays},
            {"restarted_rays", frame.restarted_rays}};
  }
};

std::string table_header() {
  return "| scene | spp | GT ms | IPR ms | speed-up | GT steps/px | IPR steps/px | SSIM | PSNR dB | capped GT/IPR |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
}

std::string table_row(const nlohmann::json& row) {
  char text[512];
  const nlohmann::json& gt = row["gt"];
  const nlohmann::json& ipr = row["ipr"];
  char psnr[32] = "inf";
  if (!row["psnr_db"].is_null()) std::snprintf(psnr, sizeof(psnr), "%.2f", row["psnr_db"].get<double>());
  std::snprintf(text, sizeof(text), "| %s | %d | %.1f | %.1f | %.2fx | %.1f | %.1f | %.5f | %s | %llu/%llu |\n",
                row["scene"].get<std::string>().c_str(), row["spp"].get<int>(), gt["median_gpu_ms"].get<double>(),
                ipr["median_gpu_ms"].get<double>(), row["speedup"].get<double>(), gt["steps_per_pixel"].get<double>(),
                ipr["steps_per_pixel"].get<double>(), row["ssim"].get<double>(), psnr,
                gt["capped_rays"].get<unsigned long long>(), ipr["capped_rays"].get<unsigned long long>());
  return text;
}

std::string pass_table(const nlohmann::json& rows) {
  std::ostringstream out;
  out << "| scene | spp | method | pass | median GPU ms | share |\n|---|---:|---|---|---:|---:|\n";
  for (const nlohmann::json& row : rows) {
    for (const char* method : {"gt", "ipr"}) {
      const nlohmann::json& runs = row[method];
      const double total = runs["median_gpu_ms"].get<double>();
      for (const auto& [name, ms] : runs["median_pass_gpu_ms"].items()) {
        char text[256];
        std::snprintf(text, sizeof(text), "| %s | %d | %s | %s | %.2f | %.0f%% |\n",
                      row["scene"].get<std::string>().c_str(), row["spp"].get<int>(), method, name.c_str(),
                      ms.get<double>(), total > 0 ? 100.0 * ms.get<double>() / total : 0.0);
        out << text;
      }
    }
  }
  return out.str();
}

void run_bench(const BenchOptions& options) {
  if (options.repeats < 1 || options.repeats > 1000) {
    throw InputError("--repeats " + std::to_string(options.repeats) + ": expected 1 to 1000");
  }
  for (int spp : options.spps) {
    SphereTraceSettings check = options.settings;
    check.samples_per_pixel = spp;
    validate(check);
  }
  std::vector<SceneSource> scenes;
  for (const std::string& name : options.scenes) scenes.push_back(load_scene(name));
  if (!options.json.empty()) check_output_path(options.json, "--json");
  if (!options.out_dir.empty()) {
    std::error_code error;
    std::filesystem::create_directories(options.out_dir, error);
    check_output_path(options.out_dir / "table.md", "--out-dir");
  }

  vk::Context context(context_options(options.device));
  std::printf("fovlab bench on %s, %dx%d, %d repeats (median GPU ms)\n%s", context.description.name.c_str(),
              options.settings.width, options.settings.height, options.repeats, table_header().c_str());
  std::fflush(stdout);

  nlohmann::json rows = nlohmann::json::array();
  std::string table = table_header();
  for (const SceneSource& scene : scenes) {
    SphereTracer tracer(context, scene);
    for (int spp : options.spps) {
      SphereTraceSettings gt_settings = options.settings;
      gt_settings.samples_per_pixel = spp;
      gt_settings.method = TraceMethod::ground_truth;
      SphereTraceSettings ipr_settings = gt_settings;
      ipr_settings.method = TraceMethod::inverted_pyramid;

      MethodRuns gt;
      MethodRuns ipr;
      // The first run of each is not timed (allocation, caches); its frame is the one measured.
      gt.frame = tracer.render(gt_settings);
      ipr.frame = tracer.render(ipr_settings);
      for (int r = 0; r < options.repeats; ++r) {  // interleaved, so both see the same machine load
        for (auto* runs : {&gt, &ipr}) {
          const SphereTraceSettings& settings = runs == &gt ? gt_settings : ipr_settings;
          const auto started = std::chrono::steady_clock::now();
          const SphereTraceResult result = tracer.render(settings);
          runs->add(result, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count());
        }
      }
      const Image gt_image = display_image(gt.frame);
      const Image ipr_image = display_image(ipr.frame);
      const analysis::PsnrResult psnr = analysis::psnr(gt_image, ipr_image);
      nlohmann::json row = {{"scene", scene.name},
                            {"spp", spp},
                            {"gt", gt.json(gt_settings)},
                            {"ipr", ipr.json(ipr_settings)},
                            {"speedup", median(gt.gpu_ms) / median(ipr.gpu_ms)},
                            {"ssim", analysis::ssim(gt_image, ipr_image).mean_ssim},
                            {"psnr_db", psnr.identical ? nlohmann::json(nullptr) : nlohmann::json(psnr.psnr_db)}};
      rows.push_back(row);
      table += table_row(row);
      std::printf("%s", table_row(row).c_str());
      std::fflush(stdout);

      if (!options.out_dir.empty()) {
        const std::string stem = scene.name + "_spp" + std::to_string(spp);
        write_colour(options.out_dir / (stem + "_gt.png"), gt.frame.colour_linear);
        write_colour(options.out_dir / (stem + "_ipr.png"), ipr.frame.colour_linear);
        write_step_heatmap(options.out_dir / (stem + "_gt_steps.png"), gt.frame, gt_settings);
        write_step_heatmap(options.out_dir / (stem + "_ipr_steps.png"), ipr.frame, ipr_settings);
      }
    }
  }
  fail_on_validation_messages(context);

  const std::string passes = pass_table(rows);
  std::printf("\nWhere the time goes (median GPU ms per pass):\n%s", passes.c_str());
  nlohmann::json report = {{"device", context.description.name},
                           {"timestamps", context.timestamp_period_ns > 0},
                           {"width", options.settings.width},
                           {"height", options.settings.height},
                           {"repeats", options.repeats},
                           {"pyramid_levels", options.settings.pyramid_levels},
                           {"min_filter_size", options.settings.min_filter_size},
                           {"max_steps", options.settings.max_steps},
                           {"hit_threshold", options.settings.hit_threshold},
                           {"time_s", options.settings.time_s},
                           {"command", reproducing_command(options)},
                           {"rows", rows}};
  if (!options.json.empty()) write_text_atomically(options.json, report.dump(2) + "\n");
  if (!options.out_dir.empty()) {
    write_text_atomically(options.out_dir / "bench.json", report.dump(2) + "\n");
    write_text_atomically(options.out_dir / "table.md",
                          "# fovlab bench\n\nCommand: `" + reproducing_command(options) + "`\n\nDevice: " +
                              context.description.name + "; " + std::to_string(options.settings.width) + "x" +
                              std::to_string(options.settings.height) + "; median of " +
                              std::to_string(options.repeats) + " runs.\n\n" + table + "\n## Passes\n\n" + passes);
  }
}

}  // namespace

void add_bench_command(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* command = app.add_subcommand("bench", "Benchmark GT against IPR: time, steps, SSIM, PSNR");
  command->add_option("--scenes", options->scenes, "Scenes, comma-separated (names or .glsl paths)")->delimiter(',');
  command->add_option("--spp", options->spps, "Samples per pixel, comma-separated (1, 4, 16)")->delimiter(',');
  command->add_option("--width", options->settings.width, "Frame width in pixels");
  command->add_option("--height", options->settings.height, "Frame height in pixels");
  command->add_option("--repeats", options->repeats, "Timed runs per method and cell (median reported)");
  command->add_option("--json", options->json, "Write the full results as JSON");
  command->add_option("--out-dir", options->out_dir, "Write images, step heat maps, table.md and bench.json here");
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  add_trace_options(*command, options->settings);
  command->callback([options] { run_bench(*options); });
}

}  // namespace fovlab::app
