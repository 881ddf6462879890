#pragma once
// Where gaze comes from during a session: the mouse (the window presenter), a recorded trace, a
// synthetic fixation/saccade generator, or a network eye tracker. A source answers "where is the
// gaze at session time t"; it never blocks for long (a network source returns its latest sample).
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "protocols/gaze/gaze_sample.h"

namespace fovlab {

class GazeSource {
 public:
  virtual ~GazeSource() = default;
  // The raw sample in use at session time time_s (may be invalid; see sanitize_gaze).
  virtual GazeSample sample(double time_s) = 0;
  // For the log header: "mouse", "trace:path", "synthetic:seed=...", "pupil:host:port".
  virtual std::string describe() const = 0;
  // Where the participant has been asked to look (an eye-tracker validation target, in screen
  // pixels), or nullopt when that target is gone. A source that simulates a participant looks
  // there; the others measure a real eye (or the mouse) and ignore it.
  virtual void set_fixation_target(std::optional<std::pair<double, double>> target_px) { (void)target_px; }
};

}  // namespace fovlab
