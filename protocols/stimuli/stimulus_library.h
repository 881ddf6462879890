#pragma once
// Renders the frames of a study's stimuli and keeps them ready for presentation. Stimuli whose
// frames do not depend on gaze (gt, ipr) are rendered once, before the first trial, so no trial
// waits on a compile or a render it could have done earlier; each frame is kept as the sRGB RGBA8
// a presenter shows, with the content hash the log records.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "protocols/gaze/gaze_sample.h"
#include "protocols/presentation/frame.h"
#include "protocols/stimuli/stimulus_spec.h"

namespace fovlab {

namespace vk {
class Context;
}
class SphereTracer;

struct PreparedFrame {
  Rgba8Frame image;
  std::string hash;  // FNV-1a-64 of the RGBA bytes (hex)
};

// The hash the log records for a presented frame.
std::string frame_hash(const Rgba8Frame& frame);

class StimulusLibrary {
 public:
  explicit StimulusLibrary(vk::Context& context);
  ~StimulusLibrary();

  // Renders every frame of the given stimuli that can be prepared ahead (ids are the caller's;
  // the same id must always name the same spec). Returns the seconds spent.
  double prepare(const std::vector<std::pair<int, StimulusSpec>>& stimuli);
  // The frame to show; prepared stimuli answer from memory, others render now with the gaze.
  const PreparedFrame& frame(int id, const StimulusSpec& spec, int frame_index, const GazeSample& gaze);
  // Always renders (replay: the frame as this build and device make it now).
  PreparedFrame render(const StimulusSpec& spec, int frame_index, const GazeSample& gaze);
  double render_seconds() const { return render_seconds_; }

 private:
  SphereTracer& tracer_for(const std::string& scene);
  vk::Context& context_;
  std::map<std::string, std::unique_ptr<SphereTracer>> tracers_;   // by scene
  std::map<int, std::vector<PreparedFrame>> prepared_;             // by stimulus id
  PreparedFrame live_;                                             // the last gaze-dependent frame
  double render_seconds_ = 0.0;
};

}  // namespace fovlab
