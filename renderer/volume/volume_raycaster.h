#pragma once
// The volume raycaster of Bruder et al. 2019 on Vulkan compute (volume_raycast.comp.glsl; the equations are in
// docs/volume-rendering.md): the full frame traces one ray per pixel; the foveated frame traces one
// ray per site of the Voronoi sampling mask (foveation/voronoi_mask.h) shifted to the gaze by whole
// pixels, with the foveated step, and rebuilds every pixel from its natural neighbours
// (voronoi_reconstruct.comp.glsl, weights from foveation/voronoi_reconstruction.h), then smooths
// over time (section 4.4). The volume lives in a storage buffer at 16 bits a voxel (the compute
// layer binds storage buffers only; the shader interpolates trilinearly itself), with min/max
// bricks of 8^3 voxels for empty-space skipping.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "core/image.h"
#include "foveation/voronoi_reconstruction.h"
#include "renderer/scene/eye_view.h"
#include "renderer/present/device_frame.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/submission.h"
#include "renderer/volume/volume_grid.h"
#include "renderer/volume/volume_scene.h"

namespace fovlab {

namespace vk {
class Context;
class ComputePipeline;
}  // namespace vk
class Srgb8Encoder;

inline constexpr int kVolumeBrickSide = 8;          // voxels a brick side
inline constexpr int kTransferTableEntries = 1024;  // the transfer function's table
inline constexpr int kTemporalHistoryFrames = 8;    // Bruder et al. 2019's n
inline constexpr int kMaxVolumeFrameSidePx = 4096;  // a frame's side (the sampling mask is twice it)

// The limits of a volume on this device (volume_grid.h): its 3-D image side and largest buffer, and
// the memory available.
VolumeLimits volume_limits(const vk::Context& context);

// The camera of a scene at a scene time: an orbit around the volume's centre. World units: the
// volume's box is centred at 0, its longest side 1; y grows downwards (as rows of an image do).
struct VolumeCameraPose {
  std::array<double, 3> eye{}, forward{}, right{}, down{};
  double tan_half_fov = 0.0;  // tan(vertical aperture / 2)
};
VolumeCameraPose camera_pose(const VolumeCamera& camera, double time_s);

inline constexpr uint32_t kMaxMaskSites = 1u << 20;

// The weights as the reconstruction pass reads them: per mask pixel, kVoronoiNeighbours words of
// index | weight << 20, the weight rounded from 1/65535 to 1/4095 (a neighbour whose weight rounds
// to 0 is dropped, as are those after it).
std::vector<uint32_t> pack_neighbours(const VoronoiReconstruction& reconstruction);

// Bricks whose samples may be seen: for each brick of kVolumeBrickSide^3 voxels (x fastest), 1 when
// the transfer table has opacity above 0 anywhere in the range of the voxels its samples and their
// trilinear reads touch (one voxel beyond each face), else 0. The CPU side of empty-space skipping.
std::vector<uint32_t> visible_bricks(const VolumeGrid& grid, const std::vector<std::array<float, 4>>& table);

// Which sites each reads, turned round: per site, the box of the mask pixels whose packed neighbours
// (pack_neighbours, what the reconstruction pass reads) name it, widened to the site's own pixel, as
// {lowest x, lowest y, highest x + 1, highest y + 1} in mask pixels; a site that no pixel reads and
// that lies in no pixel (none does: each lies in its own) would get an empty box. A foveated frame
// traces a site when its box, shifted with the gaze, meets the screen: every site a screen pixel
// reads, and every site on the screen.
std::vector<std::array<float, 4>> site_reader_boxes(const std::vector<uint32_t>& packed_neighbours,
                                                    const VoronoiMask& mask);

struct VolumeRenderSettings {
  int width_px = 0, height_px = 0;
  double time_s = 0.0;                 // scene time (the camera's orbit)
  std::optional<VolumeCamera> camera;  // instead of the scene's (benchmarks' random cameras)
  double step_voxels = 0.5;            // the base step, in voxels (of the smallest voxel side)
  bool correct_opacity = true;         // foveated: opacity corrected for the longer step
  bool foveated_step = true;           // foveated: the step grows away from the gaze
  uint32_t jitter_seed = 1;
  uint32_t frame_index = 0;  // the jitter's frame
  // Foveated: trace only the sites a screen pixel reads or that lie on the screen (site_reader_boxes);
  // false: every site within the mask's one neighbour reach of the screen (the earlier rule, for
  // comparison: the same frame, more rays).
  bool trace_read_sites_only = true;
  // A headset eye's view (renderer/scene/eye_view.h): the camera is the head, the frame the eye's
  // asymmetric frustum (and, foveated, the mask's sites on it). None: the camera's symmetric frustum.
  std::optional<EyeView> eye;
};

struct VolumeFrameResult {
  Image colour_linear;        // RGB
  uint64_t rays = 0;          // rays traced
  uint64_t sites_on_screen = 0;  // foveated: the mask's sites that lie on the screen (at this gaze)
  double traced_share = 0.0;  // rays / pixels
  double gpu_ms = 0.0;
  double reconstruct_gpu_ms = 0.0;
  std::vector<vk::PassTime> passes;
};

class VolumeRaycaster {
 public:
  // Uploads the volume, the scene's transfer table and the visible bricks. InputError when the
  // volume exceeds the device's limits.
  VolumeRaycaster(vk::Context& context, const VolumeScene& scene, const VolumeGrid& grid);
  ~VolumeRaycaster();
  VolumeRaycaster(const VolumeRaycaster&) = delete;
  VolumeRaycaster& operator=(const VolumeRaycaster&) = delete;

  // Every pixel traced.
  VolumeFrameResult render_full(const VolumeRenderSettings& settings);
  DeviceRgba8Frame display_full_on_device(const VolumeRenderSettings& settings);

  // The sampling mask and its weights for foveated frames of its screen's size, packed for the
  // device: a neighbour's site index on 20 bits and its weight on 12 (pack_neighbours). InputError
  // for a mask of 2^20 sites or more (a frame of about 4,000 pixels a side).
  void set_reconstruction(const VoronoiReconstruction& reconstruction);
  // The foveated frame for a gaze (screen pixels; rounded, and clamped to the screen so that the
  // mask covers it; not a number: the centre). `smoothing`: the temporal smoothing, whose history
  // is cleared when the view (the camera at settings.time_s) changes or by reset_history().
  VolumeFrameResult render_foveated(const VolumeRenderSettings& settings, double gaze_x_px, double gaze_y_px,
                                    bool smoothing);
  DeviceRgba8Frame display_foveated_on_device(const VolumeRenderSettings& settings, double gaze_x_px, double gaze_y_px,
                                              bool smoothing);
  void reset_history();

  // The mask's offset for a gaze: mask pixel = screen pixel + offset (foveated frames).
  std::pair<int, int> mask_offset(int width_px, int height_px, double gaze_x_px, double gaze_y_px) const;

 private:
  enum class Output { readback, display };
  VolumeFrameResult run_full(const VolumeRenderSettings& settings, Output output);
  VolumeFrameResult run_foveated(const VolumeRenderSettings& settings, double gaze_x_px, double gaze_y_px,
                                 bool smoothing, Output output);
  void ensure_frame_buffers(int width_px, int height_px);
  void write_params(const VolumeRenderSettings& settings, uint32_t mode, const std::array<int, 2>& offset,
                    const std::array<float, 2>& gaze, bool foveated);
  VolumeFrameResult finish(vk::OneTimeCommands& commands, vk::PassTimer& timer, Output output);

  vk::Context& context_;
  VolumeScene scene_;
  std::array<int, 3> size_voxels_{};
  std::array<double, 3> box_half_{};
  double base_step_world_ = 0.0;
  std::array<int, 3> brick_count_{};
  std::unique_ptr<vk::ComputePipeline> raycast_pipeline_, reconstruct_pipeline_;
  std::unique_ptr<Srgb8Encoder> encoder_;
  vk::Buffer params_, voxels_, transfer_, bricks_;
  // Foveated frames.
  std::optional<VoronoiReconstruction> reconstruction_;
  std::vector<std::array<float, 4>> site_reader_boxes_;
  vk::Buffer sites_, neighbours_, site_colours_, history_;
  // The frame.
  int width_ = 0, height_ = 0;
  vk::Buffer colour_, display_srgb8_, readback_;
  // The temporal smoothing's state.
  struct History {
    std::optional<VolumeCameraPose> view;
    std::optional<EyeView> eye;  // the eye in it, if any: each eye its own history
    int count = 0, next_slot = 0;
    std::optional<std::pair<int, int>> last_stored_offset;
  } history_state_;
  uint64_t last_rays_ = 0, last_sites_on_screen_ = 0;
};

}  // namespace fovlab
