#pragma once
// Where the top level's shaded samples spend their steps (SphereTraceSettings::step_breakdown),
// counted by the tracer's step-breakdown variant (sphere_trace.comp.glsl compiled with
// FOVLAB_STEP_BREAKDOWN; the categories are renderer/shaders/shared/sphere_trace_params.h's
// STEP_CATEGORY_*, defined in docs/benchmarks.md "Where the steps go (issue 41)").
#include <array>
#include <cstdint>
#include <span>

namespace fovlab {

inline constexpr int kStepCategoryCount = 7;
inline constexpr int kStepHistogramBins = 8;

// In gpu::STEP_CATEGORY_* order: "approach", "silhouette", "grazing", "slow_bound", "final", "miss",
// "other".
const char* step_category_name(int category);
// The steps of a histogram bin's samples: "0-1", "2", "3-4", "5-8", "9-16", "17-32", "33-64", "65+".
const char* step_histogram_bin_name(int bin);

struct StepBreakdown {
  uint64_t pixels = 0;
  uint64_t samples = 0;                                     // pixels x samples per pixel
  std::array<uint64_t, kStepCategoryCount> steps{};         // steps in each category
  std::array<uint64_t, kStepCategoryCount> samples_with{};  // samples with at least one step in it
  std::array<uint64_t, kStepHistogramBins> histogram{};     // samples by their steps
  // One-surface pixels: every sample hit, all of one material, within 5 % of the nearest's depth
  // (gpu::STEP_ONE_SURFACE_DEPTH): where the pixel's samples could march as one packet.
  uint64_t one_surface_pixels = 0;
  uint64_t one_surface_steps = 0;             // every step of their samples
  uint64_t one_surface_approach_steps = 0;    // their samples' approach steps
  uint64_t one_surface_longest_approach = 0;  // each such pixel's longest approach of a sample, summed

  uint64_t total_steps() const;
};

// The counters buffer read back (gpu::COUNTER_COUNT words) of a frame of `pixels` pixels at
// `samples_per_pixel`.
StepBreakdown read_step_breakdown(std::span<const uint32_t> counters, uint64_t pixels, uint64_t samples_per_pixel);

}  // namespace fovlab
