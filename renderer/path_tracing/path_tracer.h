#pragma once
// The path tracer of Polychronakis et al. 2021 (sections 3.1-3.2 and 4: reference frames of 128 samples per pixel
// and 32 bounces) on Vulkan compute: renderer/shaders/path_trace.comp.glsl traces a batch of samples
// per pixel per dispatch and adds them to a float buffer; the image is the sum over the sample
// count. Unidirectional, with next-event estimation on emissive triangles combined with BSDF
// sampling by multiple importance sampling (power heuristic). docs/path-tracing.md.
#include <cstdint>
#include <memory>
#include <optional>

#include "core/image.h"
#include "renderer/path_tracing/path_scene.h"
#include "renderer/scene/eye_view.h"

namespace fovlab {

namespace vk {
class Buffer;
class Context;
class ComputePipeline;
}  // namespace vk

struct PathTraceSettings {
  int width_px = 320;
  int height_px = 180;
  int samples_per_pixel = 128;        // 1 to 65536
  int max_bounces = 32;               // scattering events along a path, 0 (emitters and sky seen directly) to 1024
  uint32_t seed = 1;                  // with the pixel, sample and dimension, keys every random number
  double time_s = 0.0;                // camera time (CameraPath)
  bool next_event_estimation = true;  // off: emitters are found by BSDF sampling only (same mean, more noise)
  // A headset eye's view (renderer/scene/eye_view.h): the camera path is the head, the frame the
  // eye's asymmetric frustum. None: the camera's symmetric frustum.
  std::optional<EyeView> eye;
};

// Throws InputError naming the setting and what was expected: sizes 1 to 16384 pixels, samples and
// bounces in range, a finite time.
void validate(const PathTraceSettings& settings);

// The frame's accumulation must fit one storage buffer of the device: throws InputError
// "path tracing size WxH: expected at most M MiB in one buffer on <device>".
void check_path_trace_frame_bytes(const vk::Context& context, int width_px, int height_px);

struct PathTraceResult {
  Image image;           // RGB, linear light: the mean of samples_per_pixel samples
  double gpu_ms = 0.0;   // every batch's dispatch (0 when the queue has no timestamps)
  uint64_t samples = 0;  // width x height x samples_per_pixel
  int batches = 0;       // dispatches, each its own submission
};

// The rate of `samples` traced in `milliseconds` (GPU or wall clock), per second; 0 when no time was
// measured (a queue without timestamps).
inline double samples_per_second(uint64_t samples, double milliseconds) {
  return milliseconds > 0.0 ? double(samples) / (milliseconds / 1000.0) : 0.0;
}

class PathTracer {
 public:
  // Validates the scene (InputError), builds its BVH and uploads it.
  PathTracer(vk::Context& context, const PathScene& scene);
  ~PathTracer();
  PathTracer(const PathTracer&) = delete;
  PathTracer& operator=(const PathTracer&) = delete;

  // The same settings give the same bits on the same device. InputError for bad settings or a camera
  // whose view direction at time_s is parallel to its up vector.
  PathTraceResult render(const PathTraceSettings& settings);

  size_t triangle_count() const { return triangle_count_; }
  size_t emitter_count() const { return emitter_count_; }
  int bvh_depth() const { return bvh_depth_; }

 private:
  vk::Context& context_;
  CameraPath camera_;
  glm::vec3 sky_radiance_{0.0f};
  size_t triangle_count_ = 0;
  size_t emitter_count_ = 0;
  int bvh_depth_ = 0;
  std::unique_ptr<vk::ComputePipeline> pipeline_;
  std::unique_ptr<vk::Buffer> nodes_;
  std::unique_ptr<vk::Buffer> triangles_;
  std::unique_ptr<vk::Buffer> materials_;
  std::unique_ptr<vk::Buffer> emitters_;
};

}  // namespace fovlab
