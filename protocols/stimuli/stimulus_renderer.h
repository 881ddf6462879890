#pragma once
// One renderer per stimulus family, each doing the four things StimulusLibrary asks of a stimulus:
// refuse what can be refused without rendering (validate), ready what its images need before the
// first trial (prepare), render one image (render), and key what it keeps between images by what
// changes it. The family is the kind of scene the method renders (SceneKind), chosen once, by
// make_stimulus_renderer:
// - sphere-traced SDF scenes: gt, ipr, fipr and the sampling models on the sphere tracer;
// - pre-rendered path-traced frames (renderer/prerender/frame_cache.h), shown as they are (pt),
//   blended by zone (fpt, Polychronakis et al. 2021) or sampled by a model (pt-rmfr, ...);
// - volume scenes: volume and fvolume (Bruder et al. 2019);
// - a folder of the lab's own images (image_sequence.h), sampled by a model (img-rmfr, ...).
// A family that renders eye views (renders_eye_views) is made with the library's eye, if any, and
// draws every image as that eye sees it (stimulus_settings.h); the others are made without one.
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "protocols/stimuli/stimulus_library.h"

namespace fovlab {

enum class StimulusFamily { sphere_traced, path_traced, volume, image_sequence };
inline constexpr StimulusFamily kStimulusFamilies[] = {StimulusFamily::sphere_traced, StimulusFamily::path_traced,
                                                       StimulusFamily::volume, StimulusFamily::image_sequence};
// "sphere-traced", "path-traced", "volume", "image-sequence"
const char* stimulus_family_name(StimulusFamily family);

// The family whose renderer draws the method: its descriptor's scene kind.
StimulusFamily stimulus_family(RenderMethod method);

class StimulusRenderer {
 public:
  virtual ~StimulusRenderer() = default;
  // Whether this family draws the method (exactly one family draws each).
  virtual bool renders(RenderMethod method) const = 0;
  // Whether it can draw a headset eye's view (issue 42): the sphere-traced and volume families,
  // whose renderers take an EyeView, and the path-traced family, whose frames are pre-rendered per
  // eye (PathTraceSequence::eye). The image family's images are one view, so a headset study
  // cannot show them.
  virtual bool renders_eye_views() const { return false; }
  // Whether it can render an eye's view from a new head pose at every refresh (the head-tracked
  // view model, StimulusImage::head): the families that render from a scene (sphere-traced, volume);
  // path-traced frames are pre-rendered from one view, images are one view.
  virtual bool follows_head() const { return false; }
  // Refuses (InputError) what needs no render: the frame size against the device's limits (the
  // study config's display size: errors name its fields), a foveated method's settings.
  virtual void validate(const StimulusSpec& spec) = 0;
  // Readies, before the first trial, what the spec's images need (the scene compiled or loaded, the
  // cache's frames on disk, a sampling model's equalise solved, a Voronoi mask made); `frame_done`
  // hears each pre-rendered frame read or rendered into the cache. Gaze-independent frames are not
  // rendered here: the library renders them ahead through render().
  virtual void prepare(const StimulusSpec& spec, const std::function<void()>& frame_done) = 0;
  // One image: left on the device (PreparedFrame::on_device, no hash yet), or, for pt, as bytes with
  // their hash. Gaze-dependent methods that keep state between images render a presentation's
  // images in order (check_image_sequence).
  virtual PreparedFrame render(const StimulusSpec& spec, const StimulusImage& image) = 0;
  // The image folders this family has read -> each image's name -> SHA-256 of the bytes it read
  // (image_sequence.h); an empty object for the families that read no images.
  virtual nlohmann::json image_hashes() const { return nlohmann::json::object(); }
  // StimulusLibrary::surface_distance for this family: the sphere-traced family traces the spec's
  // scene; the others have no surface to meet (nullopt here; the library refuses them first).
  virtual std::optional<double> surface_distance(const StimulusSpec& spec, int frame, const EyeView& eye,
                                                 const std::array<double, 3>& origin_in_head,
                                                 const std::array<double, 3>& direction_in_head) {
    (void)spec, (void)frame, (void)eye, (void)origin_in_head, (void)direction_in_head;
    return std::nullopt;
  }
};

// The renderer of a family; `cache_root`: the pre-render cache's folder (path-traced family); `eye`:
// the headset eye it draws for, given to the families that render eye views (none: the desktop).
std::unique_ptr<StimulusRenderer> make_stimulus_renderer(StimulusFamily family, vk::Context& context,
                                                         const std::filesystem::path& cache_root,
                                                         const std::optional<EyeView>& eye = std::nullopt);

// The last image a scene's renderer made, for the sequence check of gaze-dependent methods.
struct LastImage {
  std::string canonical;  // spec; empty after a gaze-independent frame
  int image_index = -1;
};
// Gaze-dependent methods render a presentation's images in order: std::logic_error unless image k
// directly follows image k - 1 of the same spec (`last` is what was rendered before).
void check_image_sequence(const LastImage& last, const std::string& canonical, const StimulusImage& image);

// Each family's renderer (sphere_traced_stimuli.cpp, path_traced_stimuli.cpp, volume_stimuli.cpp,
// image_stimuli.cpp).
std::unique_ptr<StimulusRenderer> make_sphere_traced_renderer(vk::Context& context, const std::optional<EyeView>& eye);
std::unique_ptr<StimulusRenderer> make_path_traced_renderer(vk::Context& context,
                                                            const std::filesystem::path& cache_root,
                                                            const std::optional<EyeView>& eye);
std::unique_ptr<StimulusRenderer> make_volume_renderer(vk::Context& context, const std::optional<EyeView>& eye);
std::unique_ptr<StimulusRenderer> make_image_renderer(vk::Context& context);

// The study config's frame size in messages: "display.width_px x display.height_px = WxH".
extern const char* const kConfigFrameSize;
std::string config_frame_size(const StimulusSpec& spec);

}  // namespace fovlab
