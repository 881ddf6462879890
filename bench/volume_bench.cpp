#include "bench/volume_bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "analysis/report/svg_chart.h"
#include "bench/bench_runs.h"
#include "core/colour.h"
#include "core/input_error.h"
#include "core/prng.h"
#include "foveation/voronoi_reconstruction.h"
#include "renderer/volume/volume_raycaster.h"
#include "renderer/volume/volume_scene.h"

namespace fovlab::bench {
namespace {

// The q-quantile of sorted values, linear between order statistics.
double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double position = q * double(values.size() - 1);
  const size_t low = size_t(std::floor(position)), high = std::min(low + 1, values.size() - 1);
  return values[low] + (position - double(low)) * (values[high] - values[low]);
}

double mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double value : values) sum += value;
  return values.empty() ? 0.0 : sum / double(values.size());
}

std::string text(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

}  // namespace

DisplayGeometry frame_on_display(const DisplayGeometry& screen, int frame_width_px, int frame_height_px) {
  if (frame_width_px > screen.width_px || frame_height_px > screen.height_px)
    throw InputError("--width, --height: a frame of " + std::to_string(frame_width_px) + "x" +
                     std::to_string(frame_height_px) + " pixels does not fit on the display's " +
                     std::to_string(screen.width_px) + "x" + std::to_string(screen.height_px));
  DisplayGeometry frame = screen;
  frame.width_px = frame_width_px;
  frame.height_px = frame_height_px;
  frame.width_mm = screen.pixel_pitch_x_mm() * frame_width_px;
  frame.height_mm = screen.pixel_pitch_y_mm() * frame_height_px;
  return frame;
}

std::vector<VolumeBenchResult> run_volume_bench(vk::Context& context, const VolumeBenchPlan& plan,
                                                void (*progress)(const std::string& line)) {
  VoronoiMaskSettings mask_settings =
      voronoi_mask_settings(plan.width_px, plan.height_px, plan.display, plan.sigma_deg);
  const VoronoiReconstruction mask = cached_voronoi_reconstruction(mask_settings, plan.voronoi_cache);
  std::vector<VolumeBenchResult> results;
  for (const std::string& scene_name : plan.scenes) {
    const VolumeScene scene = load_volume_scene(scene_name);
    const VolumeGrid grid = load_scene_volume(scene, volume_limits(context));
    VolumeRaycaster raycaster(context, scene, grid);
    raycaster.set_reconstruction(mask);
    VolumeBenchResult result;
    result.scene = scene.name;
    result.volume_voxels = {grid.size_voxels[0], grid.size_voxels[1], grid.size_voxels[2]};
    result.sites = mask.mask.sites.size();
    result.fovea_sigma_px = mask_settings.density_sigma_px;
    // One stream a scene, so adding a scene changes no other scene's cameras and gazes.
    Pcg32 random(derive_seed(plan.seed, scene_name));
    for (int c = 0; c < plan.cameras; ++c) {
      VolumeBenchCamera camera;
      camera.azimuth_deg = random.uniform(0.0, 360.0);
      camera.elevation_deg = random.uniform(-60.0, 60.0);
      VolumeRenderSettings settings;
      settings.width_px = plan.width_px;
      settings.height_px = plan.height_px;
      settings.correct_opacity = plan.correct_opacity;
      settings.trace_read_sites_only = plan.trace_read_sites_only;
      VolumeCamera view = scene.camera;
      view.azimuth_deg = camera.azimuth_deg;
      view.elevation_deg = camera.elevation_deg;
      view.orbit_deg_per_s = 0.0;
      settings.camera = view;
      raycaster.render_full(settings);  // untimed: the device's first dispatch
      std::vector<double> full_ms;
      Image full;
      for (int f = 0; f < plan.frames; ++f) {
        settings.frame_index = uint32_t(f);
        VolumeFrameResult frame = raycaster.render_full(settings);
        full_ms.push_back(frame.gpu_ms);
        if (f == 0) full = std::move(frame.colour_linear);
      }
      camera.full_ms = median(full_ms);
      std::vector<double> foveated_ms, reconstruct_ms, shares, on_screen, rays, ssims, flips, fpsnrs;
      for (int g = 0; g < plan.gazes; ++g) {
        const double gaze_x = random.uniform(0.0, plan.width_px), gaze_y = random.uniform(0.0, plan.height_px);
        settings.frame_index = 0;
        raycaster.render_foveated(settings, gaze_x, gaze_y, false);  // untimed
        std::vector<double> frame_ms, frame_reconstruct_ms;
        Image foveated;
        for (int f = 0; f < plan.frames; ++f) {
          settings.frame_index = uint32_t(f);
          VolumeFrameResult frame = raycaster.render_foveated(settings, gaze_x, gaze_y, false);
          frame_ms.push_back(frame.gpu_ms);
          frame_reconstruct_ms.push_back(frame.reconstruct_gpu_ms);
          if (f == 0) {
            foveated = std::move(frame.colour_linear);
            shares.push_back(frame.traced_share);
            on_screen.push_back(double(frame.sites_on_screen));
            rays.push_back(double(frame.rays));
          }
        }
        foveated_ms.push_back(median(frame_ms));
        reconstruct_ms.push_back(median(frame_reconstruct_ms));
        // The mask's centre is the rounded, clamped gaze: the errors are weighted there too.
        const auto [offset_x, offset_y] = raycaster.mask_offset(plan.width_px, plan.height_px, gaze_x, gaze_y);
        // The metrics read what is shown: sRGB-encoded, clamped to the display's range.
        const FrameErrors errors = frame_errors(encode_srgb(full), encode_srgb(foveated), plan.display,
                                                double(plan.width_px - offset_x), double(plan.height_px - offset_y));
        ssims.push_back(errors.ssim);
        flips.push_back(errors.flip);
        if (errors.fpsnr_db) fpsnrs.push_back(*errors.fpsnr_db);
      }
      camera.foveated_ms = median(foveated_ms);
      camera.reconstruct_ms = median(reconstruct_ms);
      camera.traced_share = mean(shares);
      camera.sites_on_screen = mean(on_screen);
      camera.traced_rays = mean(rays);
      camera.speed_up = camera.full_ms / camera.foveated_ms;
      camera.ssim = mean(ssims);
      camera.flip = mean(flips);
      camera.fpsnr_db = mean(fpsnrs);
      result.cameras.push_back(camera);
      if (progress)
        progress(result.scene + " camera " + std::to_string(c + 1) + "/" + std::to_string(plan.cameras) + ": full " +
                 text("%.1f", camera.full_ms) + " ms, foveated " + text("%.1f", camera.foveated_ms) + " ms, " +
                 text("%.2fx", camera.speed_up));
    }
    std::vector<double> speed_ups, full, foveated, reconstruct, shares, on_screen, rays, ssims, flips, fpsnrs;
    for (const VolumeBenchCamera& camera : result.cameras) {
      speed_ups.push_back(camera.speed_up);
      full.push_back(camera.full_ms);
      foveated.push_back(camera.foveated_ms);
      reconstruct.push_back(camera.reconstruct_ms);
      shares.push_back(camera.traced_share);
      on_screen.push_back(camera.sites_on_screen);
      rays.push_back(camera.traced_rays);
      ssims.push_back(camera.ssim);
      flips.push_back(camera.flip);
      fpsnrs.push_back(camera.fpsnr_db);
    }
    result.speed_up_min = quantile(speed_ups, 0.0);
    result.speed_up_q1 = quantile(speed_ups, 0.25);
    result.speed_up_median = quantile(speed_ups, 0.5);
    result.speed_up_q3 = quantile(speed_ups, 0.75);
    result.speed_up_max = quantile(speed_ups, 1.0);
    result.full_ms = median(full);
    result.foveated_ms = median(foveated);
    result.reconstruct_ms = median(reconstruct);
    result.traced_share = median(shares);
    result.sites_on_screen = median(on_screen);
    result.traced_rays = median(rays);
    result.ssim = median(ssims);
    result.flip = median(flips);
    result.fpsnr_db = median(fpsnrs);
    results.push_back(result);
  }
  return results;
}

std::string volume_bench_markdown(const std::vector<VolumeBenchResult>& results) {
  std::string table =
      "| volume | voxels | full ms | foveated ms | speed-up median [quartiles] (min-max) | fovea s px | traced | "
      "on-screen sites | traced rays (per on-screen site) | reconstruction ms (share of foveated) | SSIM | FLIP | "
      "FPSNR dB |\n"
      "|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const VolumeBenchResult& r : results) {
    table += "| " + r.scene + " | " + std::to_string(r.volume_voxels[0]) + "x" + std::to_string(r.volume_voxels[1]) +
             "x" + std::to_string(r.volume_voxels[2]) + " | " + text("%.1f", r.full_ms) + " | " +
             text("%.1f", r.foveated_ms) + " | " + text("%.2fx", r.speed_up_median) + " [" +
             text("%.2f", r.speed_up_q1) + ", " + text("%.2f", r.speed_up_q3) + "] (" + text("%.2f", r.speed_up_min) +
             "-" + text("%.2f", r.speed_up_max) + ") | " + text("%.1f", r.fovea_sigma_px) + " | " +
             text("%.2f %%", 100.0 * r.traced_share) + " | " + text("%.0f", r.sites_on_screen) + " | " +
             text("%.0f", r.traced_rays) + " (" +
             text("%.2fx", r.sites_on_screen > 0 ? r.traced_rays / r.sites_on_screen : 0.0) + ") | " +
             text("%.2f", r.reconstruct_ms) + " (" + text("%.1f %%", 100.0 * r.reconstruct_ms / r.foveated_ms) +
             ") | " + text("%.4f", r.ssim) + " | " + text("%.4f", r.flip) + " | " + text("%.2f", r.fpsnr_db) + " |\n";
  }
  return table;
}

nlohmann::json volume_bench_json(const VolumeBenchPlan& plan, const std::vector<VolumeBenchResult>& results) {
  nlohmann::json json = {{"width_px", plan.width_px},   {"height_px", plan.height_px},
                         {"cameras", plan.cameras},     {"gazes", plan.gazes},
                         {"frames", plan.frames},       {"seed", plan.seed},
                         {"sigma_deg", plan.sigma_deg}, {"correct_opacity", plan.correct_opacity}};
  // Added fields (the earlier ones keep their names and meaning).
  json["trace_read_sites_only"] = plan.trace_read_sites_only;
  const DisplayGeometry& screen = plan.screen.width_px > 0 ? plan.screen : plan.display;  // unset: the frame's own
  json["display"] = {{"width_px", screen.width_px},
                     {"height_px", screen.height_px},
                     {"width_mm", screen.width_mm},
                     {"height_mm", screen.height_mm},
                     {"viewing_distance_mm", screen.viewing_distance_mm},
                     {"frame_width_mm", plan.display.width_mm},
                     {"frame_height_mm", plan.display.height_mm},
                     {"pixels_per_degree_at_centre", plan.display.pixels_per_degree_at_centre()}};
  json["fovea_sigma_px"] = density_sigma_px(plan.display, plan.sigma_deg);
  nlohmann::json volumes = nlohmann::json::array();
  for (const VolumeBenchResult& r : results) {
    nlohmann::json cameras = nlohmann::json::array();
    for (const VolumeBenchCamera& c : r.cameras)
      cameras.push_back({{"azimuth_deg", c.azimuth_deg},
                         {"elevation_deg", c.elevation_deg},
                         {"full_ms", c.full_ms},
                         {"foveated_ms", c.foveated_ms},
                         {"reconstruct_ms", c.reconstruct_ms},
                         {"traced_share", c.traced_share},
                         {"speed_up", c.speed_up},
                         {"ssim", c.ssim},
                         {"flip", c.flip},
                         {"fpsnr_db", c.fpsnr_db},
                         {"sites_on_screen", c.sites_on_screen},
                         {"traced_rays", c.traced_rays}});
    volumes.push_back({{"scene", r.scene},
                       {"volume_voxels", r.volume_voxels},
                       {"sites", r.sites},
                       {"speed_up",
                        {{"min", r.speed_up_min},
                         {"q1", r.speed_up_q1},
                         {"median", r.speed_up_median},
                         {"q3", r.speed_up_q3},
                         {"max", r.speed_up_max}}},
                       {"full_ms", r.full_ms},
                       {"foveated_ms", r.foveated_ms},
                       {"reconstruct_ms", r.reconstruct_ms},
                       {"traced_share", r.traced_share},
                       {"ssim", r.ssim},
                       {"flip", r.flip},
                       {"fpsnr_db", r.fpsnr_db},
                       {"cameras", cameras},
                       {"fovea_sigma_px", r.fovea_sigma_px},
                       {"sites_on_screen", r.sites_on_screen},
                       {"traced_rays", r.traced_rays}});
  }
  json["volumes"] = volumes;
  return json;
}

std::string volume_bench_svg(const std::vector<VolumeBenchResult>& results) {
  // A box plot drawn with the project's chart: per volume (x = its index) the median as a point with
  // the interquartile range as its bar, and the whole range as a second, thinner series.
  analysis::XyChart chart;
  chart.title = "Speed-up of foveated over full volume raycasting, per camera";
  chart.x_label = "volume (1 = " + (results.empty() ? std::string("-") : results[0].scene);
  for (size_t i = 1; i < results.size(); ++i) chart.x_label += ", " + std::to_string(i + 1) + " = " + results[i].scene;
  chart.x_label += ")";
  chart.y_label = "speed-up (x)";
  chart.x_min = 0.5;
  chart.x_max = double(results.size()) + 0.5;
  analysis::XySeries range, box, cameras;
  range.label = "min-max";
  box.label = "median and quartiles";
  cameras.label = "cameras";
  for (size_t i = 0; i < results.size(); ++i) {
    const double x = double(i + 1);
    range.x.push_back(x - 0.15);
    range.y.push_back(results[i].speed_up_median);
    range.y_lower.push_back(results[i].speed_up_min);
    range.y_upper.push_back(results[i].speed_up_max);
    box.x.push_back(x);
    box.y.push_back(results[i].speed_up_median);
    box.y_lower.push_back(results[i].speed_up_q1);
    box.y_upper.push_back(results[i].speed_up_q3);
    for (const VolumeBenchCamera& camera : results[i].cameras) {
      cameras.x.push_back(x + 0.15);
      cameras.y.push_back(camera.speed_up);
    }
  }
  chart.series = {box, range, cameras};
  chart.horizontal_lines = {1.0};
  return analysis::render_xy_chart_svg(chart);
}

}  // namespace fovlab::bench
