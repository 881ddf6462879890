// The sphere-traced family: SDF scenes drawn by the sphere tracer (gt, ipr, fipr, and the sampling
// models of Ye et al. 2022 on it). One tracer a scene; gaze-dependent images render in order. With an
// eye, every image is that eye's view (sphere_trace_settings).
#include <map>
#include <optional>

#include "protocols/stimuli/stimulus_renderer.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab {
namespace {

class SphereTracedStimuli final : public StimulusRenderer {
 public:
  SphereTracedStimuli(vk::Context& context, const std::optional<EyeView>& eye) : context_(context), eye_(eye) {}

  bool renders(RenderMethod method) const override { return describe(method).scene_kind == SceneKind::signed_distance; }
  bool renders_eye_views() const override { return true; }

  void validate(const StimulusSpec& spec) override {
    check_sphere_trace_frame_bytes(context_, spec.width_px, spec.height_px, kConfigFrameSize);
  }

  void prepare(const StimulusSpec& spec, const std::function<void()>&) override {
    // gt and ipr frames are rendered ahead by the library; a gaze-dependent one is rendered live, so
    // its bad settings and scene errors come now all the same, not mid-session.
    if (!describe(spec.method()).depends_on_gaze) return;
    fovlab::validate(sphere_trace_settings(spec, 0, eye_));
    tracer_for(spec.scene);
  }

  PreparedFrame render(const StimulusSpec& spec, const StimulusImage& image) override {
    SphereTracer& tracer = tracer_for(spec.scene);
    SphereTraceSettings settings = sphere_trace_settings(spec, image.frame, eye_);
    settings.outputs = TraceOutputs::display;  // encoded on the device; no step counts or mask
    LastImage& last = last_image_[spec.scene];
    const bool sequence = describe(spec.method()).depends_on_gaze;
    const std::string canonical = sequence ? spec.canonical() : std::string();
    if (sequence) {
      check_image_sequence(last, canonical, image);
      settings.foveation.gaze_x_px = image.gaze.x_px;
      settings.foveation.gaze_y_px = image.gaze.y_px;
      settings.foveation.frame_index = static_cast<uint32_t>(image.image_index);
      if (settings.sampling)
        settings.sampling = sampling_map(spec, image.gaze.x_px, image.gaze.y_px, &*settings.sampling, eye_);
    }
    // A gaze-independent frame overwrites what a sequence would continue from; a failed render
    // leaves nothing to continue from either.
    last = LastImage{};
    PreparedFrame rendered;
    rendered.on_device = tracer.render(settings).display;
    if (sequence) last = LastImage{canonical, image.image_index};
    return rendered;
  }

 private:
  SphereTracer& tracer_for(const std::string& scene) {
    auto found = tracers_.find(scene);
    if (found == tracers_.end())
      found = tracers_.emplace(scene, std::make_unique<SphereTracer>(context_, load_scene(scene))).first;
    return *found->second;
  }

  vk::Context& context_;
  std::optional<EyeView> eye_;
  std::map<std::string, std::unique_ptr<SphereTracer>> tracers_;  // by scene
  std::map<std::string, LastImage> last_image_;                   // by scene
};

}  // namespace

std::unique_ptr<StimulusRenderer> make_sphere_traced_renderer(vk::Context& context, const std::optional<EyeView>& eye) {
  return std::make_unique<SphereTracedStimuli>(context, eye);
}

}  // namespace fovlab
