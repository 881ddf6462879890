#pragma once
// Renders the frames of a study's stimuli and keeps them ready for presentation. Stimuli whose
// frames do not depend on gaze (gt, ipr, pt, volume) are rendered once, before the first trial, so
// no trial waits on a compile or a render it could have done earlier; each frame is kept as the sRGB
// RGBA8 a presenter shows, with the content hash the log records. Gaze-dependent stimuli (fipr, fpt,
// fvolume, the sampling models) are rendered live, one image per refresh, with that refresh's gaze,
// and left on the rendering device (sRGB-encoded there by the one encoder,
// renderer/present/srgb8_encoder.h), so that a presenter on that device shows them without a copy
// through the host; their hash is taken after the present (hash()). What a stimulus needs is its
// family's (stimulus_renderer.h: sphere-traced SDF scenes, pre-rendered path-traced frames from the
// pre-render cache, volume scenes), the one renderer the library asks to validate, prepare and
// render it.
//
// A headset study (issue 42) keeps one library an eye: made with that eye's EyeView, a library
// renders every spec as the eye sees it (the renderer's view and, for eccentricity, the eye's off-axis
// display: stimulus_settings.h), so its prepared frames are that eye's and StimulusImage::gaze is a
// pixel of that eye's image. Only the families that render eye views take an eye (sphere-traced,
// volume); the library refuses the others' stimuli.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/rgba8_frame.h"
#include "protocols/gaze/gaze_sample.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/present/device_frame.h"
#include "renderer/scene/eye_view.h"

namespace fovlab {

namespace vk {
class Buffer;
class Context;
}  // namespace vk
class StimulusRenderer;
enum class StimulusFamily;

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
  GazeSample gaze;      // the position used, as logged (an invalid sample holds its substitute); an
                        // eye's library: a position in that eye's image
  // A head-tracked headset session's head at this refresh, as logged (relative to its start; the
  // eye's view is eye_view_in_moved_head of it); none: head-locked. An image with a head is always
  // rendered now, never taken from the prepared frames.
  std::optional<HeadPose> head;
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
  // `cache_root`: the pre-render cache's folder (path-traced methods). `eye`: the headset eye whose
  // view every stimulus is rendered as; none: the desktop's frames, as ever.
  // `head_tracked` (an eye's library only): every image follows the head (StimulusImage::head), so
  // nothing is rendered ahead, and prepare refuses the families that cannot re-render a frame from a
  // new pose (follows_head: pre-rendered path-traced frames, images).
  explicit StimulusLibrary(vk::Context& context, const std::filesystem::path& cache_root = "stimuli/cache",
                           std::optional<EyeView> eye = std::nullopt, bool head_tracked = false);
  ~StimulusLibrary();

  // Renders every frame of the given stimuli that can be prepared ahead (ids are the caller's;
  // the same id must always name the same spec); for gaze-dependent ones (and every one of a
  // head-tracked eye) it compiles the scene, checks the settings and renders one image unseen, so
  // their errors, and what their first image builds, come before the first trial. Stimuli whose frames
  // would not fit in memory are refused before anything is rendered (check_prepared_frames_fit).
  // Returns the seconds spent.
  // `progress` (optional) hears the share done, 0 to 1, after every frame rendered or loaded.
  // An eye's library refuses first, with one InputError line naming the method, the stimuli whose
  // family cannot render an eye's view (pre-rendered path-traced frames, image stimuli).
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
  // Where a ray of the head (origin in the head, scene units, a metre each in a headset; direction,
  // any length but 0) meets the surface this eye's library shows for the spec at animation frame
  // `frame` (its scene time): the distance along the unit direction, traced by GT whatever the
  // spec's method, with the spec's step cap and its hit threshold at one pixel of this eye's image
  // (SphereTracer::hit_distance says how exact), by the tracer that renders the spec's scene (no
  // second compile). nullopt: the ray meets nothing (the sky). A headset session's gaze resting on
  // the rendered depth (issue 42). std::logic_error for a library without an eye; InputError for a
  // spec whose family shows no surface (volume: a session refuses those first).
  std::optional<double> surface_distance(const StimulusSpec& spec, int frame,
                                         const std::array<double, 3>& origin_in_head,
                                         const std::array<double, 3>& direction_in_head);
  // The eye this library renders for; nullopt: the desktop.
  const std::optional<EyeView>& eye() const { return eye_; }
  // The image folders its stimuli read -> each image's name -> SHA-256 of the bytes read (the
  // session header's image_hashes: the images shown, not the folder as it is later); an empty object
  // when no stimulus shows images.
  nlohmann::json image_hashes() const;

 private:
  // The renderer of the spec's family (stimulus_renderer.h), made once each by make_stimulus_renderer.
  // An eye's library: InputError for a family that cannot render an eye's view.
  StimulusRenderer& renderer_for(const StimulusSpec& spec);
  // render() without the read-back: most methods leave the frame on the device (no hash yet); pt
  // frames come back as bytes with their hash.
  PreparedFrame render_live(const StimulusSpec& spec, const StimulusImage& image);
  vk::Context& context_;
  std::optional<EyeView> eye_;
  bool head_tracked_ = false;
  std::map<StimulusFamily, std::unique_ptr<StimulusRenderer>> renderers_;  // every family
  std::map<int, std::vector<PreparedFrame>> prepared_;                     // by stimulus id
  PreparedFrame live_;                                                     // the last gaze-dependent image
  std::unique_ptr<vk::Buffer> readback_;                                   // frames read back from the device
  double render_seconds_ = 0.0;
};

}  // namespace fovlab
