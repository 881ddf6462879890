#include "renderer/sphere_tracing/step_breakdown.h"

#include "renderer/shaders/shared/sphere_trace_params.h"

namespace fovlab {

static_assert(kStepCategoryCount == int(gpu::STEP_CATEGORY_COUNT));
static_assert(kStepHistogramBins == int(gpu::STEP_HISTOGRAM_BINS));
static_assert(gpu::COUNTER_STEP_ONE_SURFACE_LONGEST + 2 == gpu::COUNTER_COUNT);

const char* step_category_name(int category) {
  static const char* const names[kStepCategoryCount] = {"approach", "silhouette", "grazing", "slow_bound",
                                                        "final",    "miss",       "other"};
  return category >= 0 && category < kStepCategoryCount ? names[category] : "?";
}

const char* step_histogram_bin_name(int bin) {
  static const char* const names[kStepHistogramBins] = {"0-1", "2", "3-4", "5-8", "9-16", "17-32", "33-64", "65+"};
  return bin >= 0 && bin < kStepHistogramBins ? names[bin] : "?";
}

uint64_t StepBreakdown::total_steps() const {
  uint64_t total = 0;
  for (uint64_t category_steps : steps) total += category_steps;
  return total;
}

StepBreakdown read_step_breakdown(std::span<const uint32_t> counters, uint64_t pixels, uint64_t samples_per_pixel) {
  const auto count_64 = [&](uint32_t index) { return uint64_t(counters[index]) | uint64_t(counters[index + 1]) << 32; };
  StepBreakdown breakdown;
  breakdown.pixels = pixels;
  breakdown.samples = pixels * samples_per_pixel;
  for (uint32_t c = 0; c < gpu::STEP_CATEGORY_COUNT; ++c) {
    breakdown.steps[c] = count_64(gpu::COUNTER_STEP_CATEGORY_STEPS + 2 * c);
    breakdown.samples_with[c] = counters[gpu::COUNTER_STEP_CATEGORY_SAMPLES + c];
  }
  for (uint32_t b = 0; b < gpu::STEP_HISTOGRAM_BINS; ++b)
    breakdown.histogram[b] = counters[gpu::COUNTER_STEP_HISTOGRAM + b];
  breakdown.one_surface_pixels = counters[gpu::COUNTER_STEP_ONE_SURFACE_PIXELS];
  breakdown.one_surface_steps = count_64(gpu::COUNTER_STEP_ONE_SURFACE_STEPS);
  breakdown.one_surface_approach_steps = count_64(gpu::COUNTER_STEP_ONE_SURFACE_APPROACH);
  breakdown.one_surface_longest_approach = count_64(gpu::COUNTER_STEP_ONE_SURFACE_LONGEST);
  return breakdown;
}

}  // namespace fovlab
