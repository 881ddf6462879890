#pragma once
// Renders the frames of a study's stimuli and keeps them ready for presentation. Stimuli whose
// frames do not depend on gaze (gt, ipr, pt) are rendered once, before the first trial, so no trial
// waits on a compile or a render it could have done earlier; each frame is kept as the sRGB RGBA8
// a presenter shows, with the content hash the log records. Gaze-dependent stimuli (fipr, fpt, the
// sampling models) are
// rendered live, one image per refresh, with that refresh's gaze, and left on the rendering device
// (sRGB-encoded there by the one encoder, renderer/present/srgb8_encoder.h), so that a presenter on
// that device shows them without a copy through the host; their hash is taken after the present
// (hash()). Path-traced frames (pt, fpt, pt-rmfr, ...) come
// from the pre-render cache (renderer/prerender/frame_cache.h); missing ones are rendered into it
// before the first trial. Volume stimuli (volume, fvolume) come from seed 003's raycaster; fvolume's
// sampling mask and weights are made before the first trial, never read from the Voronoi cache
// (foveation/voronoi_reconstruction.h: a cache file can be forged past its own checks).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/rgba8_frame.h"
#include "protocols/gaze/gaze_sample.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/present/device_frame.h"
#include "renderer/volume/volume_scene.h"

namespace fovlab {

namespace vk {
class Buffer;
class Context;
}  // namespace vk
class SphereTracer;
class FrameCache;
class ZoneBlender;
class FrameSampler;
class VolumeRaycaster;

struct PreparedFrame {
  Rgba8Frame image;            // the bytes (prepared frames; a live frame once hash() read it back)
  DeviceRgba8Frame on_device;  // a live frame as the renderer left it, valid until the library's next render
  std::string hash;            // FNV-1a-64 of the RGBA bytes (hex); a live frame's: empty until hash()
};

// The hash the log records for a presented frame.
std::string frame_hash(const Rgba8Frame& frame);

// One image of one presentation of a stimulus: SessionRun::present_stimulus shows, for every
// animation frame, `refreshes` images (one a refresh), so the image index is
// frame * refreshes + refresh, its position in the stimulus event's arrays (docs/log-schema.md).
struct StimulusImage {
  int frame = 0;        // animation frame of the stimulus (its scene time)
  int image_index = 0;  // position in this presentation; 0 starts a presentation
  GazeSample gaze;      // the position used, as logged (an invalid sample holds its substitute)
};

// The bytes StimulusLibrary::prepare keeps in memory for these stimuli: every frame of each one that
// does not depend on gaze, as RGBA8 (width x height x 4 bytes a frame); gaze-dependent ones (fipr,
// fpt) are rendered live and count nothing. `fovlab validate` prints this figure.
uint64_t prepared_frames_bytes(const std::vector<StimulusSpec>& stimuli);

// Refuses (InputError, one line) stimuli whose prepared frames would not fit in the memory available
// (core/memory_budget.h), naming the config fields that drive the figure (stimulus.duration_s,
// stimulus.frames_per_second, display.width_px, display.height_px), the figure and the memory
// available. `source`, when given, starts the message (the config's path).
void check_prepared_frames_fit(const std::vector<StimulusSpec>& stimuli, const std::string& source = "");

class StimulusLibrary {
 public:
  // `cache_root`: the pre-render cache's folder (path-traced methods).
  explicit StimulusLibrary(vk::Context& context, const std::filesystem::path& cache_root = "stimuli/cache");
  ~StimulusLibrary();

  // Renders every frame of the given stimuli that can be prepared ahead (ids are the caller's;
  // the same id must always name the same spec); for gaze-dependent ones it compiles the scene
  // and checks the settings, so their errors too come before the first trial. Stimuli whose frames
  // would not fit in memory are refused before anything is rendered (check_prepared_frames_fit).
  // Returns the seconds spent.
  // `progress` (optional) hears the share done, 0 to 1, after every frame rendered or loaded.
  double prepare(const std::vector<std::pair<int, StimulusSpec>>& stimuli,
                 const std::function<void(double)>& progress = {});
  // The image to show; prepared stimuli answer from memory (by frame), others render now and leave
  // it on the device (PreparedFrame::on_device), without its hash.
  const PreparedFrame& frame(int id, const StimulusSpec& spec, const StimulusImage& image);
  // The hash of a frame frame() returned: prepared ones have it; the last live one is read back from
  // the device and hashed now, which a session does after presenting it (off the path from the gaze
  // sample to the present). std::logic_error for a live frame that is no longer the last.
  const std::string& hash(const PreparedFrame& frame);
  // Always renders, and returns the bytes and their hash (replay: the image as this build and device
  // make it now).
  //
  // FIPR keeps state between the images of a presentation: with periphery refresh 2 or 4 it keeps,
  // for pixels not due, the colour of the previous image (FPT keeps none). Image 0 starts a
  // presentation afresh (it depends on nothing rendered before); image k > 0 must directly follow
  // image k - 1 of the same spec, else std::logic_error. So the images of a presentation are
  // rendered in order, each with its own gaze, and the same gazes give the same images again.
  PreparedFrame render(const StimulusSpec& spec, const StimulusImage& image);
  double render_seconds() const { return render_seconds_; }

 private:
  // The last image a scene's tracer rendered, for the sequence check of gaze-dependent methods.
  struct LastImage {
    std::string canonical;  // spec; empty after a gaze-independent frame
    int image_index = -1;
  };
  SphereTracer& tracer_for(const std::string& scene);
  // render() without the read-back: gaze-dependent methods and the sphere-traced ones leave the
  // frame on the device (no hash yet); pt frames come back as bytes with their hash.
  PreparedFrame render_live(const StimulusSpec& spec, const StimulusImage& image);
  DeviceRgba8Frame render_sphere_traced(const StimulusSpec& spec, const StimulusImage& image);
  Rgba8Frame render_path_traced(const StimulusSpec& spec, const StimulusImage& image);  // pt
  DeviceRgba8Frame blend_foveated_path_traced(const StimulusSpec& spec, const StimulusImage& image);  // fpt
  DeviceRgba8Frame sample_path_traced(const StimulusSpec& spec, const StimulusImage& image);  // pt-rmfr, ...
  DeviceRgba8Frame render_volume(const StimulusSpec& spec, const StimulusImage& image);  // volume, fvolume
  // The raycaster of a volume spec: one a scene for volume, one a scene and sampling mask for fvolume
  // (its mask and weights made anew), so that stimuli of several masks
  // switch without reloading anything; the volume itself is loaded once a scene.
  VolumeRaycaster& raycaster_for(const StimulusSpec& spec);
  // Gaze-dependent methods render a presentation's images in order: std::logic_error unless image k
  // directly follows image k - 1 of the same spec (`last` is what was rendered before).
  static void check_sequence(const LastImage& last, const std::string& canonical, const StimulusImage& image);
  // fpt's settings, size and display, without rendering (InputError).
  void check_foveated_path_traced(const StimulusSpec& spec);
  // The device's limits on the frame size, which is the study config's display size: errors name
  // its fields ([display] width_px, height_px), not a command's flags.
  void check_frame_size(const StimulusSpec& spec);
  // fpt and the path-traced sampling models: every frame in the cache before the first trial.
  void prepare_path_traced(const StimulusSpec& spec, const std::function<void()>& frame_done);
  ZoneBlender& blender();
  FrameSampler& sampler();
  vk::Context& context_;
  std::unique_ptr<FrameCache> frame_cache_;
  std::unique_ptr<ZoneBlender> blender_;
  std::string blender_frame_;  // spec and frame whose zone buffers the blender holds
  std::unique_ptr<FrameSampler> sampler_;
  std::string sampler_frame_;  // spec and frame the sampler holds
  std::optional<SamplingMap> sampler_centre_;  // the map with the gaze at the centre of the spec ...
  std::string sampler_centre_spec_;            // ... with this canonical text
  std::map<std::string, std::unique_ptr<SphereTracer>> tracers_;   // by scene
  std::map<std::string, std::unique_ptr<VolumeRaycaster>> raycasters_;  // by volume scene (and mask)
  std::map<std::string, std::pair<VolumeScene, VolumeGrid>> volumes_;   // by volume scene
  std::map<std::string, LastImage> last_image_;                    // by scene (sphere-traced and volume)
  std::map<int, std::vector<PreparedFrame>> prepared_;             // by stimulus id
  PreparedFrame live_;                                             // the last gaze-dependent image
  std::unique_ptr<vk::Buffer> readback_;                           // frames read back from the device
  double render_seconds_ = 0.0;
};

}  // namespace fovlab
