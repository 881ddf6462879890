#pragma once
// Gaze from the mouse pointer over the session window (for pilots without an eye tracker). Off the
// window, or over a letterbox, the sample is invalid ("off_screen") and the session holds the last
// valid position.
#include "protocols/gaze/gaze_source.h"
#include "display/presenter.h"

namespace fovlab {

class MouseGazeSource final : public GazeSource {
 public:
  explicit MouseGazeSource(Presenter& presenter) : presenter_(presenter) {}
  GazeSample sample(double time_s) override {
    GazeSample sample;
    sample.time_s = time_s;
    // The cursor is read now: time_s plus what the read itself took (it pumps window events).
    const double before_s = presenter_.now_s();
    const auto cursor = presenter_.cursor_px();
    sample.acquired_s = time_s + (presenter_.now_s() - before_s);
    if (!cursor) {
      sample.valid = false;
      sample.invalid_reason = "off_screen";
      return sample;
    }
    sample.x_px = cursor->first;
    sample.y_px = cursor->second;
    return sample;
  }
  std::string describe() const override { return "mouse"; }

 private:
  Presenter& presenter_;
};

}  // namespace fovlab
