#pragma once
// One frame at a time under a stimulus's sampling model (Ye et al. 2022), for the families that
// sample a frame they already have: pre-rendered path-traced frames (pt-rmfr, ...) and the lab's
// images (img-rmfr, ...). The frame is uploaded only when its key changes, the model's map with the
// gaze at the centre (equalise's solution) is solved once a stimulus, and every gaze sample gets
// its own map (FrameSampler, docs/foveation.md).
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "protocols/stimuli/stimulus_renderer.h"
#include "renderer/foveated_sampling/frame_sampler.h"

namespace fovlab {

class SampledFrameDisplay {
 public:
  // `eye`: a headset eye's, whose off-axis display the models' eccentricities are on
  // (stimulus_settings.h sampling_map); none on the desktop.
  explicit SampledFrameDisplay(vk::Context& context, std::optional<EyeView> eye = std::nullopt)
      : context_(context), eye_(std::move(eye)) {}

  // The display image of `spec` at `image`'s gaze over the frame named `frame_key`; `upload` puts
  // that frame in the sampler, and is called only when the key differs from the last one's.
  DeviceRgba8Frame show(const StimulusSpec& spec, const StimulusImage& image, const std::string& frame_key,
                        const std::function<void(FrameSampler&)>& upload);

 private:
  vk::Context& context_;
  std::optional<EyeView> eye_;
  std::unique_ptr<FrameSampler> sampler_;
  std::string frame_key_;                      // the frame the sampler holds
  std::optional<SamplingMap> centre_map_;      // the map with the gaze at the centre of the spec ...
  std::string centre_map_spec_;                // ... with this canonical text
};

}  // namespace fovlab
