// The image family: a folder of the lab's own images (image_sequence.h) sampled by one of Ye et al.
// 2022's models (img-rmfr, img-hyperbolic, img-linear, img-kfr), exactly as the path-traced family
// samples its pre-rendered frames (pt-rmfr, ...): the image of the animation frame is uploaded when
// it changes and the map follows every gaze sample (FrameSampler). No state carries from one image
// to the next, so any image can be rendered on its own.
#include <cmath>
#include <map>
#include <optional>

#include "core/input_error.h"
#include "protocols/stimuli/image_sequence.h"
#include "protocols/stimuli/stimulus_renderer.h"
#include "renderer/foveated_sampling/frame_sampler.h"

namespace fovlab {
namespace {

class ImageStimuli final : public StimulusRenderer {
 public:
  explicit ImageStimuli(vk::Context& context) : context_(context) {}

  bool renders(RenderMethod method) const override {
    return describe(method).scene_kind == SceneKind::image_sequence;
  }

  // Every image read and checked (decodes, the display's size, enough of them) before the first
  // trial; an error names the image.
  void validate(const StimulusSpec& spec) override { images(spec); }

  void prepare(const StimulusSpec& spec, const std::function<void()>& frame_done) override {
    images(spec);
    frame_done();
    sampling_map(spec, std::nan(""), std::nan(""));  // equalise solves now
  }

  PreparedFrame render(const StimulusSpec& spec, const StimulusImage& image) override {
    const std::vector<SequenceImage>& sequence = images(spec);
    const size_t index = sequence_image_index(sequence.size(), image.frame);
    const std::string canonical = spec.canonical();
    const std::string key = spec.scene + "#" + std::to_string(index);
    if (key != sampler_frame_) {
      sampler_frame_.clear();
      sampler().set_frame(sequence[index].linear);
      sampler_frame_ = key;
    }
    if (canonical != sampler_centre_spec_) {  // equalise's solution, solved once a stimulus
      sampler_centre_ = sampling_map(spec, std::nan(""), std::nan(""));
      sampler_centre_spec_ = canonical;
    }
    PreparedFrame rendered;
    rendered.on_device = sampler().display_frame_on_device(
        sampling_map(spec, image.gaze.x_px, image.gaze.y_px, &*sampler_centre_), sampling_filter(spec));
    return rendered;
  }

 private:
  // The spec's images, read once a folder and size.
  const std::vector<SequenceImage>& images(const StimulusSpec& spec) {
    const std::string key = spec.scene + "#" + std::to_string(spec.width_px) + "x" + std::to_string(spec.height_px) +
                            "#" + std::to_string(spec.frame_count);
    auto found = sequences_.find(key);
    if (found == sequences_.end())
      found = sequences_.emplace(key, read_image_sequence(spec.scene, spec.width_px, spec.height_px, spec.frame_count))
                  .first;
    return found->second;
  }
  FrameSampler& sampler() {
    if (!sampler_) sampler_ = std::make_unique<FrameSampler>(context_);
    return *sampler_;
  }

  vk::Context& context_;
  std::map<std::string, std::vector<SequenceImage>> sequences_;  // by folder, size and frame count
  std::unique_ptr<FrameSampler> sampler_;
  std::string sampler_frame_;                  // folder and image the sampler holds
  std::optional<SamplingMap> sampler_centre_;  // the map with the gaze at the centre of the spec ...
  std::string sampler_centre_spec_;            // ... with this canonical text
};

}  // namespace

std::unique_ptr<StimulusRenderer> make_image_renderer(vk::Context& context) {
  return std::make_unique<ImageStimuli>(context);
}

}  // namespace fovlab
