#pragma once
// fovlab bench, step 2: timing frames (GT and IPR interleaved; FIPR as a steady sequence) and their
// error against the GT frame.
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_results.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab::bench {

double median(std::vector<double> values);
// Wall-clock milliseconds from `started` to now.
double elapsed_ms(std::chrono::steady_clock::time_point started);

// The timings of one method in one cell over the repeats, and the frame whose error is measured.
struct MethodRuns {
  SphereTraceResult frame;
  std::vector<double> gpu_ms;
  std::vector<double> wall_ms;
  std::map<std::string, std::vector<double>> pass_ms;

  void add(const SphereTraceResult& result, double wall);
  double median_gpu_ms() const { return median(gpu_ms); }
  // Median GPU and wall ms, every run's GPU ms, median per pass, and the measured frame's steps.
  RunsResult result(const SphereTraceSettings& settings) const;
};

// GT and IPR (or GT alone) of one scene and spp: one untimed run of each (allocation, caches; its
// deterministic frame is the one measured), then `repeats` timed runs of each, interleaved so that
// all see the same machine load.
void time_interleaved(SphereTracer& tracer, const std::vector<std::pair<SphereTraceSettings, MethodRuns*>>& methods,
                      int repeats);

// FIPR's steady state with a static camera (every frame at settings.time_s): frames 0 to refresh - 1
// untimed (frame 0 starts the sequence and refreshes every pixel, the others complete one refresh
// cycle, so the history exists), then `repeats` timed frames continuing the sequence. The measured
// frame is the last timed one.
// Scene-time rate of a FIPR cell's frames (a display's refresh rate).
constexpr double kSequenceFrameRateHz = 60.0;

struct FiprSequence {
  MethodRuns runs;
  int warmup_frames = 0;
  uint32_t first_timed_frame = 0;
  uint32_t last_timed_frame = 0;
};
FiprSequence time_fipr_sequence(SphereTracer& tracer, SphereTraceSettings settings, int repeats);

}  // namespace fovlab::bench
