#pragma once
// Sphere tracing of an SDF scene: ground truth (GT, every sample traced from the camera) and the
// inverted pyramid (IPR, seed 000 section 3.1/3.2.4: each level starts its rays at the min-filtered
// depth of the level below; only the top level shades).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"
#include "renderer/scene/scene_source.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace vk {
class Context;
class ComputePipeline;
}  // namespace vk

enum class TraceMethod { ground_truth, inverted_pyramid };

const char* method_name(TraceMethod method);  // "gt" or "ipr"

struct SphereTraceSettings {
  TraceMethod method = TraceMethod::ground_truth;
  int width = 640;
  int height = 360;
  int samples_per_pixel = 1;   // 1, 4 or 16 (docs/scenes.md: sample patterns)
  float time_s = 0.0f;
  int pyramid_levels = 3;      // IPR: 2..5 levels, each with 1/4 the pixels of the one above
  int min_filter_size = 3;     // IPR: 1, 3 or 5
  int max_steps = 256;         // step cap of one ray at one level
  float hit_threshold = 0.25f;  // hit when distance < t * pixel angle * level scale * hit_threshold
};

// Validates sizes and options; throws InputError naming the flag and what was expected.
void validate(const SphereTraceSettings& settings);

struct PyramidLevelStats {
  int width = 0;
  int height = 0;
  int scale = 1;              // full-resolution pixels per level pixel along each axis
  uint64_t steps = 0;         // all steps of all rays of this level
};

struct SphereTraceResult {
  Image colour_linear;        // RGB, linear light
  Image steps_per_pixel;      // 1 channel: the pixel's own steps plus its share of the levels below
  uint64_t total_steps = 0;
  uint64_t capped_rays = 0;     // rays stopped by max_steps before a hit or leaving the bounds
  uint64_t restarted_rays = 0;  // IPR rays whose start depth was inside geometry, restarted at the bounds
  std::vector<PyramidLevelStats> levels;  // bottom (coarsest) first; GT has one
  std::vector<vk::PassTime> passes;
  double gpu_ms = 0.0;        // sum of the passes

  // All steps over the full-resolution pixel count (with spp samples the floor is about spp).
  double mean_steps_per_pixel() const { return double(total_steps) / double(colour_linear.pixel_count()); }
};

// Compiles a scene's tracer once (or takes it from the shader cache) and renders frames of it.
class SphereTracer {
 public:
  SphereTracer(vk::Context& context, const SceneSource& scene);
  ~SphereTracer();
  SphereTracer(const SphereTracer&) = delete;
  SphereTracer& operator=(const SphereTracer&) = delete;

  bool shader_from_cache() const { return shader_from_cache_; }
  SphereTraceResult render(const SphereTraceSettings& settings);

 private:
  struct FrameBuffers;
  vk::Context& context_;
  bool shader_from_cache_ = false;
  std::unique_ptr<vk::ComputePipeline> trace_pipeline_;
  std::unique_ptr<vk::ComputePipeline> min_filter_pipeline_;
  std::unique_ptr<FrameBuffers> frame_;  // buffers of the last frame layout rendered
};

}  // namespace fovlab
