#include "bench/bench_runs.h"

#include <algorithm>
#include <chrono>

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

RunsResult MethodRuns::result(const SphereTraceSettings& settings) const {
  RunsResult result;
  result.median_gpu_ms = median(gpu_ms);
  result.median_wall_ms = median(wall_ms);
  result.gpu_ms_runs = gpu_ms;
  for (const auto& [name, values] : pass_ms) result.median_pass_gpu_ms[name] = median(values);
  result.total_steps = frame.total_steps;
  result.steps_per_pixel = frame.mean_steps_per_pixel();
  result.steps_per_sample = frame.mean_steps_per_pixel() / settings.samples_per_pixel;
  result.capped_rays = frame.capped_rays;
  result.restarted_rays = frame.restarted_rays;
  return result;
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

}  // namespace fovlab::bench
