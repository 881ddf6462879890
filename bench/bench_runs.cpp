#include "bench/bench_runs.h"

#include <algorithm>
#include <chrono>

#include "metrics/flip.h"
#include "metrics/fpsnr.h"
#include "metrics/image_metrics.h"

namespace fovlab::bench {

double elapsed_ms(std::chrono::steady_clock::time_point started) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

void MethodRuns::add(const SphereTraceResult& result, double wall) {
  gpu_ms.push_back(result.gpu_ms);
  wall_ms.push_back(wall);
  for (const vk::PassTime& pass : result.passes) pass_ms[pass.name].push_back(pass.gpu_ms);
}

nlohmann::json MethodRuns::json(const SphereTraceSettings& settings) const {
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

void time_interleaved(SphereTracer& tracer, const std::vector<std::pair<SphereTraceSettings, MethodRuns*>>& methods,
                      int repeats) {
  for (const auto& [settings, runs] : methods) runs->frame = tracer.render(settings);
  for (int r = 0; r < repeats; ++r) {
    for (const auto& [settings, runs] : methods) {
      const auto started = std::chrono::steady_clock::now();
      const SphereTraceResult result = tracer.render(settings);
      runs->add(result, elapsed_ms(started));
    }
  }
}

FiprSequence time_fipr_sequence(SphereTracer& tracer, SphereTraceSettings settings, int repeats) {
  FiprSequence sequence;
  sequence.warmup_frames = settings.foveation.periphery_refresh;
  // The camera moves: frame k is at scene time time_s - (last - k) / kSequenceFrameRateHz, so the
  // last frame (the one compared with GT at time_s) carries the error of the pixels it reused.
  const float end_time_s = settings.time_s;
  const uint32_t last = static_cast<uint32_t>(sequence.warmup_frames + repeats - 1);
  const auto at_frame = [&](uint32_t frame) {
    settings.foveation.frame_index = frame;
    settings.time_s = static_cast<float>(end_time_s - double(last - frame) / kSequenceFrameRateHz);
  };
  uint32_t frame = 0;
  for (; frame < static_cast<uint32_t>(sequence.warmup_frames); ++frame) {
    at_frame(frame);
    tracer.render(settings);
  }
  sequence.first_timed_frame = frame;
  for (int r = 0; r < repeats; ++r, ++frame) {
    at_frame(frame);
    const auto started = std::chrono::steady_clock::now();
    SphereTraceResult result = tracer.render(settings);
    sequence.runs.add(result, elapsed_ms(started));
    sequence.runs.frame = std::move(result);
  }
  sequence.last_timed_frame = frame - 1;
  return sequence;
}

nlohmann::json FrameErrors::json() const {
  return {{"ssim", ssim},
          {"psnr_db", psnr_db ? nlohmann::json(*psnr_db) : nlohmann::json(nullptr)},
          {"flip", flip},
          {"fpsnr_db", fpsnr_db ? nlohmann::json(*fpsnr_db) : nlohmann::json(nullptr)}};
}

namespace {

FrameErrors errors_of(const Image& gt, const Image& test, const DisplayGeometry& display, double gaze_x_px,
                      double gaze_y_px, double flip_pixels_per_degree) {
  FrameErrors errors;
  errors.ssim = analysis::ssim(gt, test).mean_ssim;
  const analysis::PsnrResult psnr = analysis::psnr(gt, test);
  if (!psnr.identical) errors.psnr_db = psnr.psnr_db;
  errors.flip = analysis::flip(gt, test, flip_pixels_per_degree).mean_flip;
  const analysis::FpsnrResult fpsnr = analysis::fpsnr(gt, test, display, gaze_x_px, gaze_y_px);
  if (!fpsnr.identical) errors.fpsnr_db = fpsnr.fpsnr_db;
  return errors;
}

}  // namespace

FrameErrors frame_errors(const Image& gt, const Image& test, const BenchPlan& plan) {
  return errors_of(gt, test, plan.display, plan.gaze_x_px, plan.gaze_y_px, plan.flip_pixels_per_degree);
}

FrameErrors frame_errors(const Image& gt, const Image& test, const DisplayGeometry& display, double gaze_x_px,
                         double gaze_y_px) {
  return errors_of(gt, test, display, gaze_x_px, gaze_y_px, display.pixels_per_degree_at_centre());
}

}  // namespace fovlab::bench
