#pragma once
// The emulated foveated path tracer's display-rate work on the GPU (Polychronakis et al. 2021 section 3.2): a
// full-resolution linear-light frame becomes three zone buffers once per animation frame (the frame
// itself; its nearest-neighbour decimations by 2 and 4, Lanczos-3 upsampled back to full size by
// renderer/upsampling), then every gaze sample blends them (renderer/shaders/zone_blend.comp.glsl;
// reference and definitions in zone_layout.h). What a session shows is made in two passes, so that
// most pixels cost a copy (docs/foveated-path-tracing.md, "Zones and blend"): the zones are also
// kept sRGB-encoded, zone_display copies the pixels outside the bands from there and lists the band
// pixels, and zone_band blends those.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "core/image.h"
#include "foveation/display_geometry.h"
#include "foveation/zone_layout.h"
#include "renderer/present/device_frame.h"
#include "renderer/present/srgb8_encoder.h"
#include "renderer/vk/buffer.h"

namespace fovlab {

namespace vk {
class Context;
class ComputePipeline;
}  // namespace vk
class Upsampler;

enum class Zone { foveal, middle, outer };

// The three zone buffers of a width x height frame share one storage buffer, 48 bytes a pixel, which
// must fit the device's largest storage-buffer range (on lavapipe 128 MiB: 2.8 million pixels,
// e.g. 1920x1080 or 2560x1080). Throws InputError saying so, before anything is rendered.
void check_zone_frame_size(const vk::Context& context, int width_px, int height_px);

struct ZoneBlendResult {
  Image image;        // linear light, the frame's channels
  double gpu_ms = 0;  // the blend pass alone
};

class ZoneBlender {
 public:
  explicit ZoneBlender(vk::Context& context);
  ~ZoneBlender();
  ZoneBlender(const ZoneBlender&) = delete;
  ZoneBlender& operator=(const ZoneBlender&) = delete;

  // Makes the three zone buffers of a frame (1 to 4 channels). `periphery` (same size), when
  // given, is the source of the middle and outer buffers instead of the frame: Polychronakis et al. 2021's pilot
  // variant (section 4.2) whose periphery is path traced with fewer bounces. Width and height: any
  // from 1 to 16384 (InputError otherwise); the middle and outer buffers are rounded up to
  // ceil(side / 2) and ceil(side / 4) and cropped back after upsampling. A colour frame's zones
  // are also encoded to sRGB8 for display_frame. Returns the GPU ms of those passes (upsampling,
  // encoding).
  double set_frame(const Image& frame, const Image* periphery = nullptr);
  int width() const { return width_; }
  int height() const { return height_; }

  // The linear-light blend for one gaze point (pixel coordinates of the frame, finite; it may lie
  // off the screen), all the frame's channels in float. `display` must have the frame's pixel size.
  // InputError on a bad bound or size.
  ZoneBlendResult blend(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px, const ZoneBounds& bounds);
  // What a participant sees for one gaze sample, the session's display-rate path: the same blend,
  // sRGB-encoded to 8 bits a channel on the GPU (core/colour.h's encode_srgb, rounded to nearest;
  // the CPU's encoding of the linear blend up to float rounding at half steps, from two passes),
  // RGBA with alpha 255, row-major, width x height x 4 bytes. A gaze that is not a number (no
  // usable sample) shows the full-resolution frame everywhere, never a guess at where the eye is.
  // The frame needs 3 or 4 channels (InputError otherwise).
  std::vector<uint8_t> display_frame(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                                     const ZoneBounds& bounds);
  // The same frame left on the device (nothing read back), for a presenter on this device: valid
  // until the next display_frame or display_frame_on_device.
  DeviceRgba8Frame display_frame_on_device(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                                           const ZoneBounds& bounds);
  // A frame shown without foveation (the pt method): `frame` (3 or 4 channels, any size) encoded by
  // the same shader as display_frame's full-resolution zone, so that a pt frame and the foveal zone
  // of the fpt frame made from it are the same bytes. Leaves the zone buffers as they are.
  std::vector<uint8_t> encode_for_display(const Image& frame);
  // One zone buffer as the blend reads it (full size; the middle and outer ones upsampled).
  Image zone_buffer(Zone zone);

  // For timing the blend (bench/blend_cost.h): display_frame's checks; its passes, and blend's, recorded
  // into the caller's command buffer; and the buffers they read and write (the zones: foveal, middle,
  // outer, width x height float RGBA texels each; the linear blend, float RGBA; the band list, its
  // count at word 0).
  void check_display(const DisplayGeometry& display, const ZoneBounds& bounds) const;
  // The linear blend of the current zones for a gaze, into blended_linear_ (zone_blend.comp.glsl).
  void record_blend(VkCommandBuffer commands, const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                    const ZoneBounds& bounds) const;
  // display_frame's passes for a gaze, into blended_srgb8_.
  void record_display(VkCommandBuffer commands, const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                      const ZoneBounds& bounds) const;
  vk::Context& context() const { return context_; }
  const vk::Buffer& zone_buffers() const { return zones_; }
  const vk::Buffer& linear_blend_buffer() const { return blended_linear_; }
  const vk::Buffer& band_list_buffer() const { return band_list_; }

 private:
  void check_blend(const DisplayGeometry& display, const ZoneBounds& bounds) const;
  Image read_back(const vk::Buffer& buffer, VkDeviceSize offset_bytes, VkDeviceSize size_bytes);
  vk::Context& context_;
  std::unique_ptr<vk::ComputePipeline> linear_pipeline_;
  std::unique_ptr<Srgb8Encoder> encoder_;
  std::unique_ptr<vk::ComputePipeline> display_pipeline_, band_pipeline_, list_dispatch_pipeline_;
  std::unique_ptr<Upsampler> upsampler_;
  int width_ = 0;
  int height_ = 0;
  int channels_ = 0;
  vk::Buffer zones_;  // foveal, middle, outer: width x height float RGBA texels each
  vk::Buffer foveal_staging_, half_staging_, quarter_staging_, upsample_scratch_;  // set_frame's, kept for the next
  vk::Buffer blended_linear_;                                                      // float RGBA a pixel
  vk::Buffer zones_srgb8_;    // the three zones sRGB-encoded, one packed RGBA8 uint a texel (colour frames)
  vk::Buffer band_list_;      // display_frame's band pixels: a count, then x | y << 16 a pixel
  vk::Buffer band_dispatch_;  // the band pass's workgroup counts (vkCmdDispatchIndirect)
  vk::Buffer blended_srgb8_, blended_srgb8_readback_;  // one packed RGBA8 uint a pixel
};

}  // namespace fovlab
