#include "protocols/stimuli/stimulus_renderer.h"

#include <stdexcept>

namespace fovlab {

const char* stimulus_family_name(StimulusFamily family) {
  switch (family) {
    case StimulusFamily::sphere_traced:
      return "sphere-traced";
    case StimulusFamily::path_traced:
      return "path-traced";
    case StimulusFamily::volume:
      return "volume";
    case StimulusFamily::image_sequence:
      return "image-sequence";
  }
  return "?";
}

StimulusFamily stimulus_family(RenderMethod method) {
  switch (describe(method).scene_kind) {
    case SceneKind::signed_distance:
      return StimulusFamily::sphere_traced;
    case SceneKind::path_traced:
      return StimulusFamily::path_traced;
    case SceneKind::volume:
      return StimulusFamily::volume;
    case SceneKind::image_sequence:
      return StimulusFamily::image_sequence;
  }
  throw std::logic_error("stimulus_family: a method of no scene kind");
}

std::unique_ptr<StimulusRenderer> make_stimulus_renderer(StimulusFamily family, vk::Context& context,
                                                         const std::filesystem::path& cache_root,
                                                         const std::optional<EyeView>& eye) {
  switch (family) {
    case StimulusFamily::sphere_traced:
      return make_sphere_traced_renderer(context, eye);
    case StimulusFamily::path_traced:
      return make_path_traced_renderer(context, cache_root, eye);
    case StimulusFamily::volume:
      return make_volume_renderer(context, eye);
    case StimulusFamily::image_sequence:
      return make_image_renderer(context);
  }
  throw std::logic_error("make_stimulus_renderer: no such family");
}

void check_image_sequence(const LastImage& last, const std::string& canonical, const StimulusImage& image) {
  if (image.image_index < 0 ||
      (image.image_index > 0 && (last.canonical != canonical || last.image_index != image.image_index - 1)))
    throw std::logic_error("StimulusLibrary::render: image " + std::to_string(image.image_index) + " of " + canonical +
                           " does not directly follow image " + std::to_string(image.image_index - 1) +
                           " of the same presentation");
}

const char* const kConfigFrameSize = "display.width_px x display.height_px";

std::string config_frame_size(const StimulusSpec& spec) {
  return std::string(kConfigFrameSize) + " = " + std::to_string(spec.width_px) + "x" + std::to_string(spec.height_px);
}

}  // namespace fovlab
