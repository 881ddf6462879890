// The image family: a folder of the lab's own images (image_sequence.h) sampled by one of Ye et al.
// 2022's models (img-rmfr, img-hyperbolic, img-linear, img-kfr), exactly as the path-traced family
// samples its pre-rendered frames (pt-rmfr, ...): the image of the animation frame is uploaded when
// it changes and the map follows every gaze sample (FrameSampler). No state carries from one image
// to the next, so any image can be rendered on its own.
#include <cmath>
#include <map>

#include "core/input_error.h"
#include "protocols/stimuli/image_sequence.h"
#include "protocols/stimuli/sampled_frame_display.h"
#include "protocols/stimuli/stimulus_renderer.h"

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
    PreparedFrame rendered;
    rendered.on_device = sampled_.show(spec, image, spec.scene + "#" + std::to_string(index),
                                       [&](FrameSampler& sampler) { sampler.set_frame(sequence[index].linear); });
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

  vk::Context& context_;
  std::map<std::string, std::vector<SequenceImage>> sequences_;  // by folder, size and frame count
  SampledFrameDisplay sampled_{context_};
};

}  // namespace

std::unique_ptr<StimulusRenderer> make_image_renderer(vk::Context& context) {
  return std::make_unique<ImageStimuli>(context);
}

}  // namespace fovlab
