// The volume family: volume scenes drawn by the raycaster of Bruder et al. 2019 (docs/
// volume-rendering.md), every pixel traced (volume) or rays at the sites of a Voronoi sampling mask
// around each gaze sample (fvolume). fvolume's mask and weights are made before the first trial,
// never read from the Voronoi cache (foveation/voronoi_reconstruction.h: a cache file can be forged
// past its own checks). With an eye, every image is that eye's view and fvolume's mask is made on
// the eye's display (volume_render_settings, voronoi_mask_settings).
#include <map>
#include <optional>

#include "core/input_error.h"
#include "protocols/stimuli/stimulus_renderer.h"
#include "renderer/volume/volume_raycaster.h"
#include "renderer/volume/volume_scene.h"

namespace fovlab {
namespace {

class VolumeStimuli final : public StimulusRenderer {
 public:
  VolumeStimuli(vk::Context& context, const std::optional<EyeView>& eye) : context_(context), eye_(eye) {}

  bool renders(RenderMethod method) const override { return describe(method).scene_kind == SceneKind::volume; }
  bool renders_eye_views() const override { return true; }
  bool follows_head() const override { return true; }

  void validate(const StimulusSpec& spec) override {
    if (spec.width_px < 1 || spec.height_px < 1 || spec.width_px > kMaxVolumeFrameSidePx ||
        spec.height_px > kMaxVolumeFrameSidePx)
      throw InputError(config_frame_size(spec) + ": expected 1 to " + std::to_string(kMaxVolumeFrameSidePx) +
                       " pixels a side for " + std::string(spec.method_name()));
  }

  // The volume is loaded and fvolume's mask made now, not at the first trial.
  void prepare(const StimulusSpec& spec, const std::function<void()>&) override { raycaster_for(spec); }

  PreparedFrame render(const StimulusSpec& spec, const StimulusImage& image) override {
    VolumeRaycaster& raycaster = raycaster_for(spec);
    // Head-tracked: the eye where the head carries it at this refresh.
    const std::optional<EyeView> eye =
        image.head && eye_ ? std::optional(eye_view_in_moved_head(*eye_, *image.head)) : eye_;
    VolumeRenderSettings settings = volume_render_settings(spec, image.frame, eye);
    LastImage& last = last_image_[spec.scene];
    PreparedFrame rendered;
    if (spec.method() == RenderMethod::volume_raycast) {
      last = LastImage{};
      settings.frame_index = static_cast<uint32_t>(image.frame);
      rendered.on_device = raycaster.display_full_on_device(settings);
      return rendered;
    }
    // fvolume: images in order, each with its own gaze; the temporal smoothing's history starts
    // afresh with each presentation, so a presentation's images depend on nothing rendered before it.
    const std::string canonical = spec.canonical();
    check_image_sequence(last, canonical, image);
    last = LastImage{};
    if (image.image_index == 0) raycaster.reset_history();
    settings.frame_index = static_cast<uint32_t>(image.image_index);
    rendered.on_device =
        raycaster.display_foveated_on_device(settings, image.gaze.x_px, image.gaze.y_px, temporal_smoothing(spec));
    last = LastImage{canonical, image.image_index};
    return rendered;
  }

 private:
  // The raycaster of a spec: one a scene for volume, one a scene and sampling mask for fvolume (its
  // mask and weights made anew), so that stimuli of several masks switch without reloading
  // anything; the volume itself is loaded once a scene.
  VolumeRaycaster& raycaster_for(const StimulusSpec& spec) {
    const bool foveated = spec.method() == RenderMethod::foveated_volume_raycast;
    const std::optional<VoronoiMaskSettings> mask =
        foveated ? std::optional(voronoi_mask_settings(spec, eye_)) : std::nullopt;
    const std::string key = mask ? spec.scene + "#" + voronoi_settings_key(*mask) : spec.scene;
    auto found = raycasters_.find(key);
    if (found != raycasters_.end()) return *found->second;
    auto volume = volumes_.find(spec.scene);
    if (volume == volumes_.end()) {
      VolumeScene scene = load_volume_scene(spec.scene);
      VolumeGrid grid = load_scene_volume(scene, volume_limits(context_));
      volume = volumes_.emplace(spec.scene, std::pair{std::move(scene), std::move(grid)}).first;
    }
    auto raycaster = std::make_unique<VolumeRaycaster>(context_, volume->second.first, volume->second.second);
    // Made anew, never read from the Voronoi cache: a cache file passes every check of its own bytes
    // once its hash and reach are recomputed after an edit, and a participant must see the mask the
    // algorithm makes (so replay, which makes it too, compares frames with the algorithm's). It takes
    // a fraction of a second at the study configs' sizes (docs/volume-rendering.md, "Cache").
    if (mask) raycaster->set_reconstruction(make_voronoi_reconstruction(*mask));
    return *raycasters_.emplace(key, std::move(raycaster)).first->second;
  }

  vk::Context& context_;
  std::optional<EyeView> eye_;
  std::map<std::string, std::unique_ptr<VolumeRaycaster>> raycasters_;  // by volume scene (and mask)
  std::map<std::string, std::pair<VolumeScene, VolumeGrid>> volumes_;   // by volume scene
  std::map<std::string, LastImage> last_image_;                         // by scene
};

}  // namespace

std::unique_ptr<StimulusRenderer> make_volume_renderer(vk::Context& context, const std::optional<EyeView>& eye) {
  return std::make_unique<VolumeStimuli>(context, eye);
}

}  // namespace fovlab
