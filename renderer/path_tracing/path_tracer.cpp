#include "renderer/path_tracing/path_tracer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/trigonometric.hpp>

#include "core/input_error.h"
#include "core/number_text.h"
#include "renderer/path_tracing/bvh.h"
#include "renderer/path_tracing/gpu_scene.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/path_trace_params.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace {

constexpr int kMaxSizePx = 16384;
constexpr int kMaxSamplesPerPixel = 65536;
constexpr int kMaxBounces = 1024;
// Samples one dispatch traces, about: small enough that a dispatch of long paths stays well under a
// driver's timeout (and lavapipe answers between batches), large enough to fill a GPU.
constexpr uint64_t kSamplesPerBatch = uint64_t(1) << 19;
constexpr int kMaxSamplesPerPixelPerBatch = 16;
constexpr uint32_t kFlagNextEventEstimation = 1u;

using gpu::PathTraceParams;

void copy3(gpu::vec4& out, const glm::vec3& v) {
  out[0] = v.x;
  out[1] = v.y;
  out[2] = v.z;
  out[3] = 0.0f;
}

template <typename T>
std::unique_ptr<vk::Buffer> device_buffer(vk::Context& context, const std::vector<T>& items, const char* what) {
  const VkDeviceSize bytes = std::max<VkDeviceSize>(sizeof(T) * items.size(), sizeof(T));
  if (bytes > context.max_storage_buffer_bytes)
    throw InputError(std::string("scene: ") + std::to_string(items.size()) + " " + what + ": expected at most " +
                     std::to_string(context.max_storage_buffer_bytes / sizeof(T)) + " on " + context.description.name);
  vk::Buffer staging(context, bytes, vk::MemoryUse::host_upload);
  std::memset(staging.mapped(), 0, bytes);
  if (!items.empty()) std::memcpy(staging.mapped(), items.data(), sizeof(T) * items.size());
  staging.flush();
  auto buffer = std::make_unique<vk::Buffer>(context, bytes, vk::MemoryUse::device_local);
  vk::OneTimeCommands commands(context);
  vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  const VkBufferCopy region{0, 0, bytes};
  vkCmdCopyBuffer(commands.handle(), staging.handle(), buffer->handle(), 1, &region);
  vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
  commands.submit_and_wait();
  return buffer;
}

void check_range(const char* name, int value, int low, int high) {
  if (value < low || value > high)
    throw InputError(std::string(name) + " " + std::to_string(value) + ": expected " + std::to_string(low) + " to " +
                     std::to_string(high));
}

}  // namespace

void validate(const PathTraceSettings& settings) {
  check_range("path tracing width", settings.width_px, 1, kMaxSizePx);
  check_range("path tracing height", settings.height_px, 1, kMaxSizePx);
  check_range("path tracing samples per pixel", settings.samples_per_pixel, 1, kMaxSamplesPerPixel);
  check_range("path tracing max bounces", settings.max_bounces, 0, kMaxBounces);
  if (!std::isfinite(settings.time_s))
    throw InputError("path tracing time " + exact_number_text(settings.time_s) + " s: expected a finite number");
}

PathTracer::PathTracer(vk::Context& context, const PathScene& scene) : context_(context) {
  validate(scene);
  camera_ = scene.camera;
  sky_radiance_ = scene.sky_radiance;
  const Bvh bvh = build_bvh(scene);
  const PackedScene packed = pack_scene(scene, bvh);
  triangle_count_ = packed.triangles.size();
  emitter_count_ = packed.emitters.size();
  bvh_depth_ = bvh.depth;
  nodes_ = device_buffer(context, packed.nodes, "BVH nodes");
  triangles_ = device_buffer(context, packed.triangles, "triangles");
  materials_ = device_buffer(context, packed.materials, "materials");
  emitters_ = device_buffer(context, packed.emitters, "emitters");
  pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::path_trace_spirv, 5, sizeof(PathTraceParams));
}

PathTracer::~PathTracer() = default;

void check_path_trace_frame_bytes(const vk::Context& context, int width_px, int height_px) {
  const VkDeviceSize accumulation_bytes = VkDeviceSize(width_px) * VkDeviceSize(height_px) * 4 * sizeof(float);
  if (accumulation_bytes > context.max_storage_buffer_bytes)
    throw InputError("path tracing size " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                     ": expected at most " + std::to_string(context.max_storage_buffer_bytes >> 20) +
                     " MiB in one buffer on " + context.description.name);
}

PathTraceResult PathTracer::render(const PathTraceSettings& settings) {
  validate(settings);
  check_path_trace_frame_bytes(context_, settings.width_px, settings.height_px);
  const uint32_t width = uint32_t(settings.width_px), height = uint32_t(settings.height_px);
  const uint64_t pixels = uint64_t(width) * height;
  const VkDeviceSize accumulation_bytes = pixels * 4 * sizeof(float);

  const CameraPose pose = camera_pose_at(camera_, settings.time_s);
  const glm::vec3 forward = glm::normalize(pose.target - pose.eye);
  const glm::vec3 side = glm::cross(forward, glm::normalize(camera_.up));
  if (!(glm::length(side) > 1e-6f))
    throw InputError("scene camera at " + exact_number_text(settings.time_s) +
                     " s: view direction parallel to the up vector: expected them apart");
  const float tan_half = std::tan(glm::radians(camera_.vertical_fov_deg) * 0.5f);
  const float aspect = float(width) / float(height);
  const glm::vec3 right = glm::normalize(side);
  const glm::vec3 up = glm::cross(right, forward);

  PathTraceParams params{};
  copy3(params.eye, pose.eye);
  copy3(params.right, right * (tan_half * aspect));
  copy3(params.up, up * tan_half);
  copy3(params.forward, forward);
  if (settings.eye) {
    // The camera is the head; the eye sits at its position along the head's right, up and backward
    // axes, turned by its orientation, and its frustum's centre tan-angles go into `forward`, their
    // half spans into `right` and `up` (the shader's ray: forward + ndc.x right + ndc.y up).
    const EyeViewShaderValues eye = eye_view_shader_values(*settings.eye);
    const glm::mat3 head(right, up, -forward);
    const glm::vec3 q(eye.orientation[0], eye.orientation[1], eye.orientation[2]);
    const float w = eye.orientation[3];
    glm::mat3 turn(1.0f);
    for (int axis = 0; axis < 3; ++axis) turn[axis] += 2.0f * glm::cross(q, glm::cross(q, turn[axis]) + w * turn[axis]);
    const glm::vec3 eye_right = head * turn[0], eye_up = head * turn[1], eye_forward = -(head * turn[2]);
    const auto& t = eye.tan_angles;  // left, right, up, down
    copy3(params.eye, pose.eye + head * glm::vec3(eye.position[0], eye.position[1], eye.position[2]));
    copy3(params.right, eye_right * (0.5f * (t[1] - t[0])));
    copy3(params.up, eye_up * (0.5f * (t[2] - t[3])));
    copy3(params.forward, eye_forward + eye_right * (0.5f * (t[0] + t[1])) + eye_up * (0.5f * (t[2] + t[3])));
  }
  copy3(params.sky_radiance, sky_radiance_);
  params.size[0] = width;
  params.size[1] = height;
  params.max_bounces = uint32_t(settings.max_bounces);
  params.seed = settings.seed;
  params.emitter_count = settings.next_event_estimation ? uint32_t(emitter_count_) : 0u;
  params.flags = settings.next_event_estimation ? kFlagNextEventEstimation : 0u;

  vk::Buffer accumulation(context_, accumulation_bytes, vk::MemoryUse::device_local);
  vk::Buffer readback(context_, accumulation_bytes, vk::MemoryUse::host_readback);
  const VkBuffer buffers[] = {nodes_->handle(), triangles_->handle(), materials_->handle(), emitters_->handle(),
                              accumulation.handle()};
  const auto per_batch = uint32_t(std::clamp<uint64_t>(kSamplesPerBatch / pixels, 1, kMaxSamplesPerPixelPerBatch));
  const auto total = uint32_t(settings.samples_per_pixel);

  PathTraceResult result;
  vk::PassTimer timer(context_, 1);
  for (uint32_t begin = 0; begin < total; begin += per_batch) {
    params.sample_begin = begin;
    params.sample_count = std::min(per_batch, total - begin);
    const bool last = begin + params.sample_count == total;
    vk::OneTimeCommands commands(context_);
    VkCommandBuffer cmd = commands.handle();
    timer.reset(cmd);
    if (begin == 0) {
      vkCmdFillBuffer(cmd, accumulation.handle(), 0, VK_WHOLE_SIZE, 0);
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    } else {
      vk::compute_to_compute_barrier(cmd);  // the previous batch's sums, written in an earlier submission
    }
    timer.begin(cmd, "path_trace");
    pipeline_->dispatch_2d(cmd, buffers, &params, width, height);
    timer.end(cmd);
    if (last) {
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
      const VkBufferCopy region{0, 0, accumulation_bytes};
      vkCmdCopyBuffer(cmd, accumulation.handle(), readback.handle(), 1, &region);
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                         VK_ACCESS_HOST_READ_BIT);
    }
    commands.submit_and_wait();
    for (const vk::PassTime& pass : timer.results()) result.gpu_ms += pass.gpu_ms;
    ++result.batches;
  }

  readback.invalidate();
  const auto* sums = static_cast<const float*>(readback.mapped());
  result.image = Image(int(width), int(height), 3);
  for (size_t p = 0; p < pixels; ++p)
    for (size_t c = 0; c < 3; ++c) result.image.pixels[p * 3 + c] = sums[p * 4 + c] / float(total);
  result.samples = pixels * total;
  return result;
}

}  // namespace fovlab
