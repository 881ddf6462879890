#include "renderer/volume/volume_raycaster.h"

#include <algorithm>
#include <numbers>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/input_error.h"
#include "core/memory_budget.h"
#include "renderer/present/srgb8_encoder.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/volume_params.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/image_texels.h"

namespace fovlab {
namespace {

constexpr uint32_t kModeFull = 0, kModeSites = 1;
constexpr uint32_t kNoSlot = 0xFFFFFFFFu;
// Phong with a headlight: ambient, diffuse, specular, shininess.
constexpr std::array<float, 4> kShading{0.3f, 0.7f, 0.25f, 24.0f};

using gpu::VolumeRayParams;
using gpu::VoronoiReconstructParams;

std::array<double, 3> normalised(const std::array<double, 3>& v) {
  const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / length, v[1] / length, v[2] / length};
}

std::array<double, 3> cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

bool same_view(const VolumeCameraPose& a, const VolumeCameraPose& b) {
  return a.eye == b.eye && a.forward == b.forward && a.tan_half_fov == b.tan_half_fov;
}

// A device-local buffer holding `size` bytes, copied through a staging buffer.
void upload(const vk::Context& context, vk::Buffer& target, const void* bytes, VkDeviceSize size) {
  target = vk::Buffer(context, size, vk::MemoryUse::device_local);
  vk::Buffer staging(context, size, vk::MemoryUse::host_upload);
  std::memcpy(staging.mapped(), bytes, size);
  staging.flush();
  vk::OneTimeCommands commands(context);
  const VkBufferCopy region{0, 0, size};
  vkCmdCopyBuffer(commands.handle(), staging.handle(), target.handle(), 1, &region);
  commands.submit_and_wait();
}

}  // namespace

VolumeLimits volume_limits(const vk::Context& context) {
  VolumeLimits limits;
  limits.max_side_voxels =
      int(std::min<uint32_t>(context.max_image_side_3d ? context.max_image_side_3d : 2048, 1u << 15));
  limits.max_bytes = std::min<uint64_t>(context.max_storage_buffer_bytes, uint64_t(1) << 32);
  if (const std::optional<AvailableMemory> memory = available_memory())
    limits.max_bytes = std::min(limits.max_bytes, memory->bytes / 2);  // the grid on the host and its upload
  return limits;
}

VolumeCameraPose camera_pose(const VolumeCamera& camera, double time_s) {
  const double azimuth = (camera.azimuth_deg + camera.orbit_deg_per_s * time_s) * std::numbers::pi / 180.0;
  const double elevation = camera.elevation_deg * std::numbers::pi / 180.0;
  VolumeCameraPose pose;
  // Azimuth 0 looks along +z with x to the right and y down, as an image of the slices is read.
  pose.eye = {-camera.distance * std::cos(elevation) * std::sin(azimuth), -camera.distance * std::sin(elevation),
              -camera.distance * std::cos(elevation) * std::cos(azimuth)};
  pose.forward = normalised({-pose.eye[0], -pose.eye[1], -pose.eye[2]});
  pose.right = normalised(cross({0.0, 1.0, 0.0}, pose.forward));
  pose.down = cross(pose.forward, pose.right);
  pose.tan_half_fov = std::tan(camera.vertical_fov_deg * std::numbers::pi / 360.0);
  return pose;
}

std::vector<uint32_t> visible_bricks(const VolumeGrid& grid, const std::vector<std::array<float, 4>>& table) {
  const std::array<int, 3>& size = grid.size_voxels;
  std::array<int, 3> bricks{};
  for (int a = 0; a < 3; ++a) bricks[size_t(a)] = (size[size_t(a)] + kVolumeBrickSide - 1) / kVolumeBrickSide;
  // The opacity's prefix count over the table: any entry above 0 in [i, j] is one lookup.
  std::vector<int> opaque_prefix(table.size() + 1, 0);
  for (size_t i = 0; i < table.size(); ++i) opaque_prefix[i + 1] = opaque_prefix[i] + (table[i][3] > 0.0f ? 1 : 0);
  const double last = double(table.size() - 1);
  std::vector<uint32_t> visible(static_cast<size_t>(bricks[0]) * size_t(bricks[1]) * size_t(bricks[2]), 0u);
  for (int bz = 0; bz < bricks[2]; ++bz)
    for (int by = 0; by < bricks[1]; ++by)
      for (int bx = 0; bx < bricks[0]; ++bx) {
        uint16_t low = 65535, high = 0;
        const int b[3] = {bx, by, bz};
        int from[3], to[3];
        for (int a = 0; a < 3; ++a) {
          from[a] = std::max(0, b[a] * kVolumeBrickSide - 1);
          to[a] = std::min(size[size_t(a)] - 1, (b[a] + 1) * kVolumeBrickSide);
        }
        for (int z = from[2]; z <= to[2]; ++z)
          for (int y = from[1]; y <= to[1]; ++y)
            for (int x = from[0]; x <= to[0]; ++x) {
              const uint16_t value = grid.at(x, y, z);
              low = std::min(low, value);
              high = std::max(high, value);
            }
        // One entry wider on each side than the exact range: the shader's float position may land an
        // ulp beyond it.
        const size_t first = size_t(std::max(0.0, std::floor(low / 65535.0 * last) - 1.0));
        const size_t end = std::min(size_t(std::ceil(high / 65535.0 * last)) + 1, table.size() - 1);
        const bool seen = opaque_prefix[end + 1] - opaque_prefix[first] > 0;
        visible[(size_t(bz) * size_t(bricks[1]) + size_t(by)) * size_t(bricks[0]) + size_t(bx)] = seen ? 1u : 0u;
      }
  return visible;
}

std::vector<uint32_t> pack_neighbours(const VoronoiReconstruction& reconstruction) {
  std::vector<uint32_t> packed(reconstruction.neighbour_sites.size(), 0u);
  for (size_t pixel = 0; pixel < packed.size(); pixel += kVoronoiNeighbours)
    for (size_t k = 0; k < size_t(kVoronoiNeighbours); ++k) {
      const uint32_t weight = (uint32_t(reconstruction.neighbour_weights[pixel + k]) * 4095u + 32767u) / 65535u;
      if (weight == 0) break;  // heaviest first: nothing after it counts either
      packed[pixel + k] = (reconstruction.neighbour_sites[pixel + k] & (kMaxMaskSites - 1)) | (weight << 20);
    }
  return packed;
}

std::vector<std::array<float, 4>> site_reader_boxes(const std::vector<uint32_t>& packed_neighbours,
                                                    const VoronoiMask& mask) {
  constexpr float kNone = 3.0e38f;
  std::vector<std::array<float, 4>> boxes(mask.sites.size(), {kNone, kNone, -kNone, -kNone});
  const auto widen = [&](size_t site, int x, int y) {
    std::array<float, 4>& box = boxes[site];
    box[0] = std::min(box[0], float(x));
    box[1] = std::min(box[1], float(y));
    box[2] = std::max(box[2], float(x + 1));
    box[3] = std::max(box[3], float(y + 1));
  };
  for (size_t site = 0; site < mask.sites.size(); ++site)
    widen(site, int(std::floor(mask.sites[site].x_px)), int(std::floor(mask.sites[site].y_px)));
  if (packed_neighbours.size() != size_t(mask.width_px) * size_t(mask.height_px) * kVoronoiNeighbours)
    throw std::invalid_argument("site_reader_boxes: neighbours of another mask");
  for (int y = 0; y < mask.height_px; ++y)
    for (int x = 0; x < mask.width_px; ++x) {
      const size_t base = (size_t(y) * size_t(mask.width_px) + size_t(x)) * kVoronoiNeighbours;
      for (size_t k = 0; k < size_t(kVoronoiNeighbours); ++k) {
        const uint32_t entry = packed_neighbours[base + k];
        if ((entry >> 20) == 0) break;  // as the reconstruction pass reads them
        const size_t site = entry & (kMaxMaskSites - 1);
        if (site < boxes.size()) widen(site, x, y);
      }
    }
  return boxes;
}

VolumeRaycaster::VolumeRaycaster(vk::Context& context, const VolumeScene& scene, const VolumeGrid& grid)
    : context_(context),
      scene_(scene),
      raycast_pipeline_(std::make_unique<vk::ComputePipeline>(context, shaders::volume_raycast_spirv, 7, 0)),
      reconstruct_pipeline_(std::make_unique<vk::ComputePipeline>(context, shaders::voronoi_reconstruct_spirv, 4,
                                                                  sizeof(VoronoiReconstructParams))),
      encoder_(std::make_unique<Srgb8Encoder>(context)),
      params_(context, sizeof(VolumeRayParams), vk::MemoryUse::host_upload) {
  const VolumeLimits limits = volume_limits(context);
  check_volume_size({grid.size_voxels[0], grid.size_voxels[1], grid.size_voxels[2]}, limits, "volume of " + scene.name);
  if (grid.values.size() != grid.voxel_count())
    throw std::invalid_argument("VolumeRaycaster: a grid whose values do not match its size");
  size_voxels_ = grid.size_voxels;
  std::array<double, 3> extent{};
  double longest = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double spacing =
        std::isfinite(grid.spacing[size_t(a)]) && grid.spacing[size_t(a)] > 0.0 ? grid.spacing[size_t(a)] : 1.0;
    extent[size_t(a)] = spacing * grid.size_voxels[size_t(a)];
    longest = std::max(longest, extent[size_t(a)]);
  }
  double smallest_voxel = 1.0;
  for (int a = 0; a < 3; ++a) {
    box_half_[size_t(a)] = 0.5 * extent[size_t(a)] / longest;
    smallest_voxel = std::min(smallest_voxel, 2.0 * box_half_[size_t(a)] / grid.size_voxels[size_t(a)]);
  }
  base_step_world_ = smallest_voxel;  // times step_voxels per frame
  const std::vector<std::array<float, 4>> table = transfer_table(scene.transfer_function, kTransferTableEntries);
  const std::vector<uint32_t> bricks = visible_bricks(grid, table);
  for (int a = 0; a < 3; ++a)
    brick_count_[size_t(a)] = (size_voxels_[size_t(a)] + kVolumeBrickSide - 1) / kVolumeBrickSide;

  std::vector<uint16_t> voxels = grid.values;
  if (voxels.size() % 2 == 1) voxels.push_back(0);  // whole words
  upload(context, voxels_, voxels.data(), voxels.size() * sizeof(uint16_t));
  upload(context, transfer_, table.data(), table.size() * sizeof(table[0]));
  upload(context, bricks_, bricks.data(), bricks.size() * sizeof(uint32_t));
  // Placeholders until a mask is set (every binding needs a buffer).
  sites_ = vk::Buffer(context, 16, vk::MemoryUse::device_local);
  site_colours_ = vk::Buffer(context, 16, vk::MemoryUse::device_local);
}

VolumeRaycaster::~VolumeRaycaster() = default;

void VolumeRaycaster::ensure_frame_buffers(int width_px, int height_px) {
  if (width_px < 1 || height_px < 1 || width_px > 16384 || height_px > 16384)
    throw SettingError("width x height", " " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                                             ": expected 1 to 16384 pixels a side");
  if (width_px == width_ && height_px == height_) return;
  const VkDeviceSize pixels = VkDeviceSize(width_px) * VkDeviceSize(height_px);
  // The largest buffers a frame binds: the temporal smoothing's history (8 frames of 16 bytes a
  // pixel) and the weights (8 words a mask pixel, 4 mask pixels a pixel), 128 bytes a pixel each.
  if (pixels * 128 > context_.max_storage_buffer_bytes)
    throw InputError("volume frame of " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                     " pixels: expected at most " + std::to_string(context_.max_storage_buffer_bytes / 128) +
                     " pixels on " + context_.description.name + " (its largest buffer binding holds " +
                     std::to_string(context_.max_storage_buffer_bytes) + " bytes; 128 bytes a pixel)");
  colour_ = vk::Buffer(context_, pixels * vk::kRgba32fTexelBytes, vk::MemoryUse::device_local);
  readback_ = vk::Buffer(context_, pixels * vk::kRgba32fTexelBytes, vk::MemoryUse::host_readback);
  display_srgb8_ = vk::Buffer(context_, pixels * 4, vk::MemoryUse::device_local);
  history_ = vk::Buffer();
  history_state_ = History{};
  width_ = width_px;
  height_ = height_px;
}

void VolumeRaycaster::write_params(const VolumeRenderSettings& settings, uint32_t mode,
                                   const std::array<int, 2>& offset, const std::array<float, 2>& gaze, bool foveated) {
  if (!(settings.step_voxels >= 0.05 && settings.step_voxels <= 16.0))
    throw SettingError("step_voxels", " " + std::to_string(settings.step_voxels) + ": expected 0.05 to 16 voxels");
  if (!std::isfinite(settings.time_s)) throw SettingError("time_s", ": expected a finite scene time");
  const VolumeCameraPose pose = camera_pose(settings.camera.value_or(scene_.camera), settings.time_s);
  VolumeRayParams p{};
  const auto put3 = [](gpu::vec4& out, const std::array<double, 3>& v, double w) {
    out[0] = float(v[0]);
    out[1] = float(v[1]);
    out[2] = float(v[2]);
    out[3] = float(w);
  };
  const double step_world = base_step_world_ * settings.step_voxels;
  put3(p.eye, pose.eye, 0.0);
  put3(p.forward, pose.forward, pose.tan_half_fov);
  put3(p.right, pose.right, double(settings.width_px) / double(settings.height_px));
  put3(p.down, pose.down, 0.0);
  if (settings.eye) {
    // The camera is the head (x right, y up = -down, z backwards = -forward); the eye sits at its
    // position in it, turned by its orientation. The shader's ray is forward + ndc.x tan_half aspect
    // right + ndc.y tan_half down: with tan_half and aspect 1, the frustum's centre tan-angles go
    // into forward and its half spans into right and down.
    const EyeViewShaderValues eye = eye_view_shader_values(*settings.eye);
    const std::array<double, 3> up{-pose.down[0], -pose.down[1], -pose.down[2]};
    const std::array<double, 3> back{-pose.forward[0], -pose.forward[1], -pose.forward[2]};
    const auto in_world = [&](const std::array<double, 3>& v) {
      std::array<double, 3> w{};
      for (int a = 0; a < 3; ++a)
        w[size_t(a)] = pose.right[size_t(a)] * v[0] + up[size_t(a)] * v[1] + back[size_t(a)] * v[2];
      return w;
    };
    const std::array<double, 3> q{eye.orientation[0], eye.orientation[1], eye.orientation[2]};
    const double qw = eye.orientation[3];
    const auto turned = [&](const std::array<double, 3>& v) {  // v + 2 q x (q x v + w v)
      const std::array<double, 3> c = cross(q, v);
      const std::array<double, 3> t = cross(q, {c[0] + qw * v[0], c[1] + qw * v[1], c[2] + qw * v[2]});
      return in_world({v[0] + 2.0 * t[0], v[1] + 2.0 * t[1], v[2] + 2.0 * t[2]});
    };
    const std::array<double, 3> right = turned({1.0, 0.0, 0.0}), eye_up = turned({0.0, 1.0, 0.0});
    const std::array<double, 3> forward_axis = turned({0.0, 0.0, -1.0});
    const std::array<double, 3> eye_offset = in_world({eye.position[0], eye.position[1], eye.position[2]});
    const auto& t = eye.tan_angles;  // left, right, up, down
    const double mid_x = 0.5 * (double(t[0]) + t[1]), half_x = 0.5 * (double(t[1]) - t[0]);
    const double mid_up = 0.5 * (double(t[2]) + t[3]), half_y = 0.5 * (double(t[2]) - t[3]);
    std::array<double, 3> eye_position{}, forward{}, right_span{}, down_span{};
    for (int a = 0; a < 3; ++a) {
      const size_t i = size_t(a);
      eye_position[i] = pose.eye[i] + eye_offset[i];
      forward[i] = forward_axis[i] + mid_x * right[i] + mid_up * eye_up[i];
      right_span[i] = half_x * right[i];
      down_span[i] = -half_y * eye_up[i];
    }
    put3(p.eye, eye_position, 0.0);
    put3(p.forward, forward, 1.0);
    put3(p.right, right_span, 1.0);
    put3(p.down, down_span, 0.0);
  }
  put3(p.box_half, box_half_, step_world);
  double diagonal = 0.0;
  for (int a = 0; a < 3; ++a) {
    p.voxel_scale[a] = float(size_voxels_[size_t(a)] / (2.0 * box_half_[size_t(a)]));
    diagonal += 4.0 * box_half_[size_t(a)] * box_half_[size_t(a)];
    p.volume_size[a] = uint32_t(size_voxels_[size_t(a)]);
    p.brick_count[a] = uint32_t(brick_count_[size_t(a)]);
  }
  // Every step and every skipped brick is an iteration: the most a ray through the box can take.
  // Capped (2^24), so no volume's shape can make a ray run for ever.
  p.voxel_scale[3] = float(std::min(
      std::ceil(std::sqrt(diagonal) / step_world) + 3.0 * (brick_count_[0] + brick_count_[1] + brick_count_[2]) + 8.0,
      16777216.0));
  p.background[3] = float(0.5 * base_step_world_);  // the reference step of the transfer function's opacities
  p.volume_size[3] = kVolumeBrickSide;
  p.screen[0] = uint32_t(settings.width_px);
  p.screen[1] = uint32_t(settings.height_px);
  p.screen[2] = mode;
  p.screen[3] = mode == kModeSites ? uint32_t(reconstruction_->mask.sites.size()) : 0u;
  p.mask_offset[0] = offset[0];
  p.mask_offset[1] = offset[1];
  p.mask_offset[2] = int32_t(settings.jitter_seed);
  p.mask_offset[3] = int32_t(settings.frame_index);
  p.gaze[0] = gaze[0];
  p.gaze[1] = gaze[1];
  p.gaze[2] = foveated && settings.foveated_step ? 1.0f : 0.0f;
  p.gaze[3] = foveated && settings.correct_opacity ? 1.0f : 0.0f;
  std::copy(kShading.begin(), kShading.end(), p.shading.begin());
  if (mode == kModeSites) {
    const float reach = reconstruction_->neighbour_reach_px + 1.0f;
    p.sites_window[0] = -reach;
    p.sites_window[1] = -reach;
    p.sites_window[2] = float(settings.width_px) + reach;
    p.sites_window[3] = float(settings.height_px) + reach;
    p.brick_count[3] = settings.trace_read_sites_only ? 1u : 0u;
  }
  std::memcpy(params_.mapped(), &p, sizeof p);
  params_.flush();
}

VolumeFrameResult VolumeRaycaster::finish(vk::OneTimeCommands& commands, vk::PassTimer& timer, Output output) {
  VkCommandBuffer cmd = commands.handle();
  if (output == Output::display) {
    encoder_->record(cmd, colour_.handle(), display_srgb8_.handle(), width_, height_);
  } else {
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    const VkBufferCopy region{0, 0, colour_.size_bytes()};
    vkCmdCopyBuffer(cmd, colour_.handle(), readback_.handle(), 1, &region);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                       VK_ACCESS_HOST_READ_BIT);
  }
  commands.submit_and_wait();
  VolumeFrameResult result;
  result.passes = timer.results();
  for (const vk::PassTime& pass : result.passes) {
    result.gpu_ms += pass.gpu_ms;
    if (pass.name == "voronoi_reconstruct") result.reconstruct_gpu_ms += pass.gpu_ms;
  }
  result.rays = last_rays_;
  result.sites_on_screen = last_sites_on_screen_;
  result.traced_share = double(last_rays_) / (double(width_) * double(height_));
  if (output == Output::readback) {
    readback_.invalidate();
    result.colour_linear = vk::unpack_rgba_texels(static_cast<const float*>(readback_.mapped()), width_, height_, 3);
  }
  return result;
}

VolumeFrameResult VolumeRaycaster::run_full(const VolumeRenderSettings& settings, Output output) {
  ensure_frame_buffers(settings.width_px, settings.height_px);
  write_params(settings, kModeFull, {0, 0}, {0.0f, 0.0f}, false);
  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, 2);
  timer.reset(cmd);
  const VkBuffer buffers[] = {params_.handle(), voxels_.handle(), transfer_.handle(),    bricks_.handle(),
                              sites_.handle(),  colour_.handle(), site_colours_.handle()};
  timer.begin(cmd, "volume_full");
  raycast_pipeline_->dispatch_2d(cmd, buffers, nullptr, uint32_t(width_), uint32_t(height_));
  timer.end(cmd);
  vk::compute_to_compute_barrier(cmd);
  last_rays_ = uint64_t(width_) * uint64_t(height_);
  last_sites_on_screen_ = 0;
  return finish(commands, timer, output);
}

VolumeFrameResult VolumeRaycaster::render_full(const VolumeRenderSettings& settings) {
  return run_full(settings, Output::readback);
}

DeviceRgba8Frame VolumeRaycaster::display_full_on_device(const VolumeRenderSettings& settings) {
  run_full(settings, Output::display);
  return DeviceRgba8Frame{&context_, display_srgb8_.handle(), width_, height_};
}

void VolumeRaycaster::set_reconstruction(const VoronoiReconstruction& reconstruction) {
  if (reconstruction.mask.sites.empty() ||
      reconstruction.neighbour_sites.size() !=
          size_t(reconstruction.mask.width_px) * size_t(reconstruction.mask.height_px) * kVoronoiNeighbours)
    throw std::invalid_argument("VolumeRaycaster::set_reconstruction: an empty or inconsistent mask");
  ensure_frame_buffers(reconstruction.settings.screen_width_px, reconstruction.settings.screen_height_px);
  if (reconstruction.mask.sites.size() >= kMaxMaskSites)
    throw InputError("sampling mask of a " + std::to_string(reconstruction.settings.screen_width_px) + "x" +
                     std::to_string(reconstruction.settings.screen_height_px) +
                     " frame: " + std::to_string(reconstruction.mask.sites.size()) + " sites: expected fewer than " +
                     std::to_string(kMaxMaskSites) + " (a smaller frame or a larger density_sigma_deg)");
  const std::vector<uint32_t> neighbours = pack_neighbours(reconstruction);
  site_reader_boxes_ = site_reader_boxes(neighbours, reconstruction.mask);
  // The sites' positions, then their readers' boxes (the shader reads both from one buffer).
  std::vector<float> sites;
  sites.reserve(reconstruction.mask.sites.size() * 6);
  for (const MaskSite& site : reconstruction.mask.sites) sites.insert(sites.end(), {site.x_px, site.y_px});
  for (const std::array<float, 4>& box : site_reader_boxes_) sites.insert(sites.end(), box.begin(), box.end());
  upload(context_, sites_, sites.data(), sites.size() * sizeof(float));
  upload(context_, neighbours_, neighbours.data(), neighbours.size() * sizeof(uint32_t));
  site_colours_ =
      vk::Buffer(context_, reconstruction.mask.sites.size() * 2 * sizeof(uint32_t), vk::MemoryUse::device_local);
  reconstruction_ = reconstruction;
  reconstruction_->neighbour_sites = {};  // on the device now: the host keeps the sites and reach only
  reconstruction_->neighbour_weights = {};
  history_state_ = History{};
}

std::pair<int, int> VolumeRaycaster::mask_offset(int width_px, int height_px, double gaze_x_px,
                                                 double gaze_y_px) const {
  const auto whole = [](double gaze, int side) {
    if (!std::isfinite(gaze)) return side / 2;
    return int(std::clamp(std::floor(gaze + 0.5), 0.0, double(side)));
  };
  return {width_px - whole(gaze_x_px, width_px), height_px - whole(gaze_y_px, height_px)};
}

void VolumeRaycaster::reset_history() { history_state_ = History{}; }

VolumeFrameResult VolumeRaycaster::run_foveated(const VolumeRenderSettings& settings, double gaze_x_px,
                                                double gaze_y_px, bool smoothing, Output output) {
  if (!reconstruction_) throw std::logic_error("VolumeRaycaster: no sampling mask set");
  if (reconstruction_->settings.screen_width_px != settings.width_px ||
      reconstruction_->settings.screen_height_px != settings.height_px)
    throw std::invalid_argument(
        "VolumeRaycaster: a mask of a " + std::to_string(reconstruction_->settings.screen_width_px) + "x" +
        std::to_string(reconstruction_->settings.screen_height_px) + " screen for a " +
        std::to_string(settings.width_px) + "x" + std::to_string(settings.height_px) + " frame");
  ensure_frame_buffers(settings.width_px, settings.height_px);
  const auto [offset_x, offset_y] = mask_offset(width_, height_, gaze_x_px, gaze_y_px);
  const std::array<float, 2> gaze{float(width_ - offset_x), float(height_ - offset_y)};
  write_params(settings, kModeSites, {offset_x, offset_y}, gaze, true);

  // The temporal smoothing: a new view clears the history; a frame is stored when the mask moved.
  VoronoiReconstructParams reconstruct{
      {uint32_t(width_), uint32_t(height_)},
      {uint32_t(reconstruction_->mask.width_px), uint32_t(reconstruction_->mask.height_px)},
      {offset_x, offset_y},
      0,
      kNoSlot};
  if (smoothing) {
    if (history_.handle() == VK_NULL_HANDLE) {
      history_ = vk::Buffer(
          context_, VkDeviceSize(width_) * VkDeviceSize(height_) * vk::kRgba32fTexelBytes * kTemporalHistoryFrames,
          vk::MemoryUse::device_local);
      history_state_ = History{};
    }
    const VolumeCameraPose view = camera_pose(settings.camera.value_or(scene_.camera), settings.time_s);
    if (!history_state_.view || !same_view(*history_state_.view, view) || history_state_.eye != settings.eye)
      history_state_ = History{view, settings.eye, 0, 0, std::nullopt};
    reconstruct.history_count = uint32_t(history_state_.count);
    const std::pair<int, int> offset{offset_x, offset_y};
    if (history_state_.last_stored_offset != offset) {
      reconstruct.store_slot = uint32_t(history_state_.next_slot);
      history_state_.next_slot = (history_state_.next_slot + 1) % kTemporalHistoryFrames;
      history_state_.count = std::min(history_state_.count + 1, kTemporalHistoryFrames);
      history_state_.last_stored_offset = offset;
    }
  }
  const vk::Buffer& history = history_.handle() != VK_NULL_HANDLE ? history_ : colour_;  // unread without smoothing
  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, 3);
  timer.reset(cmd);
  const VkBuffer ray_buffers[] = {params_.handle(), voxels_.handle(), transfer_.handle(),    bricks_.handle(),
                                  sites_.handle(),  colour_.handle(), site_colours_.handle()};
  const uint32_t sites = uint32_t(reconstruction_->mask.sites.size());
  const uint32_t groups = (sites + 63) / 64;
  timer.begin(cmd, "volume_sites");
  raycast_pipeline_->dispatch_groups(cmd, ray_buffers, nullptr, std::min<uint32_t>(groups, 65535),
                                     (groups + 65534) / 65535);
  timer.end(cmd);
  vk::compute_to_compute_barrier(cmd);
  const VkBuffer reconstruct_buffers[] = {neighbours_.handle(), site_colours_.handle(), colour_.handle(),
                                          history.handle()};
  timer.begin(cmd, "voronoi_reconstruct");
  reconstruct_pipeline_->dispatch_2d(cmd, reconstruct_buffers, &reconstruct, uint32_t(width_), uint32_t(height_));
  timer.end(cmd);
  vk::compute_to_compute_barrier(cmd);
  // The rays: the sites the shader traces (inside the window, and with their readers' box meeting
  // the screen), in the same float arithmetic.
  const float reach = reconstruction_->neighbour_reach_px + 1.0f;
  uint64_t rays = 0, on_screen = 0;
  for (size_t i = 0; i < reconstruction_->mask.sites.size(); ++i) {
    const MaskSite& site = reconstruction_->mask.sites[i];
    const float x = site.x_px - float(offset_x), y = site.y_px - float(offset_y);
    if (x >= 0.0f && y >= 0.0f && x < float(width_) && y < float(height_)) ++on_screen;
    if (!(x >= -reach && y >= -reach && x <= float(width_) + reach && y <= float(height_) + reach)) continue;
    if (settings.trace_read_sites_only) {
      const std::array<float, 4>& box = site_reader_boxes_[i];
      if (box[0] - float(offset_x) >= float(width_) || box[1] - float(offset_y) >= float(height_) ||
          box[2] - float(offset_x) <= 0.0f || box[3] - float(offset_y) <= 0.0f)
        continue;
    }
    ++rays;
  }
  last_rays_ = rays;
  last_sites_on_screen_ = on_screen;
  return finish(commands, timer, output);
}

VolumeFrameResult VolumeRaycaster::render_foveated(const VolumeRenderSettings& settings, double gaze_x_px,
                                                   double gaze_y_px, bool smoothing) {
  return run_foveated(settings, gaze_x_px, gaze_y_px, smoothing, Output::readback);
}

DeviceRgba8Frame VolumeRaycaster::display_foveated_on_device(const VolumeRenderSettings& settings, double gaze_x_px,
                                                             double gaze_y_px, bool smoothing) {
  run_foveated(settings, gaze_x_px, gaze_y_px, smoothing, Output::display);
  return DeviceRgba8Frame{&context_, display_srgb8_.handle(), width_, height_};
}

}  // namespace fovlab
