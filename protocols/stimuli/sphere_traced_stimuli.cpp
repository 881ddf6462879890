// The sphere-traced family: SDF scenes drawn by the sphere tracer (gt, ipr, fipr, and the sampling
// models of Ye et al. 2022 on it). One tracer a scene; gaze-dependent images render in order. With an
// eye, every image is that eye's view (sphere_trace_settings).
#include <algorithm>
#include <cmath>
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
  bool follows_head() const override { return true; }

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
    // Head-tracked: the eye where the head carries it at this refresh (the frame's camera stays the head's start).
    const std::optional<EyeView> eye =
        image.head && eye_ ? std::optional(eye_view_in_moved_head(*eye_, *image.head)) : eye_;
    SphereTraceSettings settings = sphere_trace_settings(spec, image.frame, eye);
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

  // GT's march at the scene time of `frame`, with the spec's step cap and its hit threshold at the
  // eye's pixel angle (tan(up) - tan(down) over the image's height, as the tracer's frames take it).
  std::optional<double> surface_distance(const StimulusSpec& spec, int frame, const EyeView& eye,
                                         const std::array<double, 3>& origin_in_head,
                                         const std::array<double, 3>& direction_in_head) override {
    // The step cap and threshold of the spec (its settings made once: a sampling model's solve a refresh
    // would cost far more than the ray).
    auto march = march_of_.find(spec.canonical());
    if (march == march_of_.end()) {
      const SphereTraceSettings settings = sphere_trace_settings(spec, frame, eye);
      march = march_of_.emplace(spec.canonical(), std::pair{settings.max_steps, double(settings.hit_threshold)}).first;
    }
    const EyeFieldOfView& fov = eye.field_of_view;
    const double pixel_angle_rad = (std::tan(fov.angle_up_rad) - std::tan(fov.angle_down_rad)) / spec.height_px;
    SurfaceRay ray;
    ray.time_s = static_cast<float>(spec.frame_time_s(frame));  // as sphere_trace_settings' time_s
    ray.origin_in_head = origin_in_head;
    ray.direction_in_head = direction_in_head;
    ray.hit_angle_rad = std::min(pixel_angle_rad * march->second.second, 1.0);  // (hit_distance's limit)
    ray.max_steps = march->second.first;
    return tracer_for(spec.scene).hit_distance(ray);
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
  std::map<std::string, std::pair<int, double>> march_of_;        // by spec: max_steps, hit_threshold
};

}  // namespace

std::unique_ptr<StimulusRenderer> make_sphere_traced_renderer(vk::Context& context, const std::optional<EyeView>& eye) {
  return std::make_unique<SphereTracedStimuli>(context, eye);
}

}  // namespace fovlab
