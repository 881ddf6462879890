#include "protocols/stimuli/sampled_frame_display.h"

#include <cmath>

#include "protocols/stimuli/stimulus_settings.h"

namespace fovlab {

DeviceRgba8Frame SampledFrameDisplay::show(const StimulusSpec& spec, const StimulusImage& image,
                                           const std::string& frame_key,
                                           const std::function<void(FrameSampler&)>& upload) {
  if (!sampler_) sampler_ = std::make_unique<FrameSampler>(context_);
  if (frame_key != frame_key_) {
    frame_key_.clear();  // an upload that throws leaves no frame named
    upload(*sampler_);
    frame_key_ = frame_key;
  }
  const std::string canonical = spec.canonical();
  if (canonical != centre_map_spec_) {  // equalise's solution, solved once a stimulus
    centre_map_ = sampling_map(spec, std::nan(""), std::nan(""), nullptr, eye_);
    centre_map_spec_ = canonical;
  }
  return sampler_->display_frame_on_device(sampling_map(spec, image.gaze.x_px, image.gaze.y_px, &*centre_map_, eye_),
                                           sampling_filter(spec));
}

}  // namespace fovlab
