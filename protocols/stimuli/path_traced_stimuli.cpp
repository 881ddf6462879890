// The path-traced family: pre-rendered path-traced frames (renderer/prerender/frame_cache.h), shown
// as they are (pt), blended by the gaze of each refresh into three zones (fpt, the emulated foveated
// path tracer of Polychronakis et al. 2021) or sampled by a sampling model (pt-rmfr, pt-hyperbolic,
// pt-linear, pt-kfr: Ye et al. 2022's models on the frames). No state carries from one image to the
// next, so any image can be rendered on its own. For a headset eye, the frames are that eye's
// (pre-rendered per eye: path_traced_frames(spec, eye)) and the zones and models are on its off-axis
// display.
#include <cmath>

#include "core/input_error.h"
#include "protocols/stimuli/sampled_frame_display.h"
#include "protocols/stimuli/stimulus_renderer.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/zone_blend/zone_blender.h"

namespace fovlab {
namespace {

class PathTracedStimuli final : public StimulusRenderer {
 public:
  PathTracedStimuli(vk::Context& context, const std::filesystem::path& cache_root, const std::optional<EyeView>& eye)
      : context_(context), eye_(eye), frame_cache_(context, cache_root), sampled_(context, eye) {}

  bool renders(RenderMethod method) const override { return describe(method).scene_kind == SceneKind::path_traced; }
  bool renders_eye_views() const override { return true; }

  void validate(const StimulusSpec& spec) override {
    try {
      check_path_trace_frame_bytes(context_, spec.width_px, spec.height_px);
      if (spec.method() == RenderMethod::foveated_path_traced)
        check_zone_frame_size(context_, spec.width_px, spec.height_px);
    } catch (const InputError& error) {
      throw InputError(config_frame_size(spec) + ": " + error.what());
    }
    if (spec.method() == RenderMethod::foveated_path_traced) {  // its display and zones
      stimulus_display(spec, eye_);
      check_zone_bounds(zone_bounds(spec));
    }
  }

  void prepare(const StimulusSpec& spec, const std::function<void()>& frame_done) override {
    if (!describe(spec.method()).depends_on_gaze)
      return;  // pt frames are loaded (or rendered) by the library's render loop
    // Every frame on disk and readable before the first trial: missing ones are rendered now (fovlab
    // prerender does the same ahead of time, on as many machines as wanted), a damaged one is an
    // error naming its file now rather than mid-session.
    for (const PathTraceSequence& sequence : path_traced_frames(spec, eye_).sequences)
      for (int frame = 0; frame < sequence.frame_count; ++frame) {
        frame_cache_.frame(sequence, frame);
        frame_done();
      }
    if (is_sampling_model(spec.method()))
      sampling_map(spec, std::nan(""), std::nan(""), nullptr, eye_);  // equalise solves now
  }

  PreparedFrame render(const StimulusSpec& spec, const StimulusImage& image) override {
    PreparedFrame rendered;
    if (spec.method() == RenderMethod::path_traced) {
      rendered.image = shown(spec, image);
      rendered.hash = frame_hash(rendered.image);
    } else if (spec.method() == RenderMethod::foveated_path_traced) {
      rendered.on_device = blended(spec, image);
    } else {
      rendered.on_device = sampled(spec, image);
    }
    return rendered;
  }

 private:
  // pt: the frame encoded by the shader that encodes fpt's frames, so that the two agree to the
  // byte wherever fpt shows its full-resolution zone.
  Rgba8Frame shown(const StimulusSpec& spec, const StimulusImage& image) {
    const PathTracedFrames frames = path_traced_frames(spec, eye_);
    Rgba8Frame frame;
    frame.width = spec.width_px;
    frame.height = spec.height_px;
    frame.rgba = blender().encode_for_display(frame_cache_.frame(frames.sequences[0], image.frame));
    return frame;
  }

  // fpt: the zone buffers change with the animation frame, the blend with every gaze sample.
  DeviceRgba8Frame blended(const StimulusSpec& spec, const StimulusImage& image) {
    const PathTracedFrames frames = path_traced_frames(spec, eye_);
    const std::string key = spec.canonical() + "#" + std::to_string(image.frame);
    if (key != blender_frame_) {
      blender_frame_.clear();
      const Image foveal = frame_cache_.frame(frames.sequences[0], image.frame);
      if (frames.sequences.size() > 1) {
        const Image periphery = frame_cache_.frame(frames.sequences[1], image.frame);
        blender().set_frame(foveal, &periphery);
      } else {
        blender().set_frame(foveal);
      }
      blender_frame_ = key;
    }
    // Blended and sRGB-encoded on the GPU. A gaze sample that is not a number (none usable, not even
    // a substitute) shows the frame itself: the full-resolution zone everywhere.
    return blender().display_frame_on_device(stimulus_display(spec, eye_), image.gaze.x_px, image.gaze.y_px,
                                             zone_bounds(spec));
  }

  // The sampling models: as fpt, the frame is uploaded when the animation frame changes and the map
  // follows every gaze sample.
  DeviceRgba8Frame sampled(const StimulusSpec& spec, const StimulusImage& image) {
    return sampled_.show(spec, image, spec.canonical() + "#" + std::to_string(image.frame), [&](FrameSampler& sampler) {
      sampler.set_frame(frame_cache_.frame(path_traced_frames(spec, eye_).sequences[0], image.frame));
    });
  }

  ZoneBlender& blender() {
    if (!blender_) blender_ = std::make_unique<ZoneBlender>(context_);
    return *blender_;
  }

  vk::Context& context_;
  std::optional<EyeView> eye_;  // a headset eye's frames (their own cache folders), or the desktop's
  FrameCache frame_cache_;
  std::unique_ptr<ZoneBlender> blender_;
  std::string blender_frame_;  // spec and frame whose zone buffers the blender holds
  SampledFrameDisplay sampled_;
};

}  // namespace

std::unique_ptr<StimulusRenderer> make_path_traced_renderer(vk::Context& context,
                                                            const std::filesystem::path& cache_root,
                                                            const std::optional<EyeView>& eye) {
  return std::make_unique<PathTracedStimuli>(context, cache_root, eye);
}

}  // namespace fovlab
