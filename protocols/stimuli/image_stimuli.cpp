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
    const std::vector<SequenceImage>& sequence = images(spec).shown;
    const size_t index = sequence_image_index(sequence.size(), image.frame);
    PreparedFrame rendered;
    rendered.on_device = sampled_.show(spec, image, spec.scene + "#" + std::to_string(index),
                                       [&](FrameSampler& sampler) { sampler.set_frame(sequence[index].linear); });
    return rendered;
  }

  nlohmann::json image_hashes() const override {
    nlohmann::json hashes = nlohmann::json::object();
    for (const auto& [key, loaded] : sequences_) {
      const std::string& folder = key.folder;
      if (hashes.contains(folder) && hashes[folder] != loaded.hashes)
        throw InputError(folder + ": its images changed while the session read them: expected the same bytes each time");
      hashes[folder] = loaded.hashes;
    }
    return hashes;
  }

 private:
  struct SequenceKey {
    std::string folder;
    int width_px = 0, height_px = 0, frame_count = 0;
    auto operator<=>(const SequenceKey&) const = default;
  };

  // The spec's images, read once a folder, size and frame count.
  const LoadedImageSequence& images(const StimulusSpec& spec) {
    const SequenceKey key{spec.scene, spec.width_px, spec.height_px, spec.frame_count};
    auto found = sequences_.find(key);
    if (found == sequences_.end())
      found = sequences_.emplace(key, load_image_sequence(spec.scene, spec.width_px, spec.height_px, spec.frame_count))
                  .first;
    return found->second;
  }

  vk::Context& context_;
  std::map<SequenceKey, LoadedImageSequence> sequences_;
  SampledFrameDisplay sampled_{context_};
};

}  // namespace

std::unique_ptr<StimulusRenderer> make_image_renderer(vk::Context& context) {
  return std::make_unique<ImageStimuli>(context);
}

}  // namespace fovlab
