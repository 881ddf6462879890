#include "protocols/gaze/tracker_validation.h"

#include <array>
#include <cmath>
#include <optional>

namespace fovlab {

DisplayGeometry display_geometry(const DisplayConfig& display) {
  return display_from_size(display.width_px, display.height_px, display.width_mm, display.height_mm,
                           display.viewing_distance_mm);
}

ValidationTarget measure_validation_target(const DisplayGeometry& display, double target_x_px, double target_y_px,
                                           const std::vector<GazeSample>& samples) {
  ValidationTarget target;
  target.x_px = target_x_px;
  target.y_px = target_y_px;
  double sum_x = 0.0, sum_y = 0.0, sum_squares = 0.0;
  int pairs = 0;
  std::optional<std::array<double, 2>> previous;  // the last sample, when it was valid
  std::optional<double> previous_acquired_s;
  for (const GazeSample& sample : samples) {
    if (sample.acquired_s && previous_acquired_s && *sample.acquired_s == *previous_acquired_s) continue;  // read again
    previous_acquired_s = sample.acquired_s;
    ++target.samples;
    const double x_px = round_gaze_px(sample.x_px), y_px = round_gaze_px(sample.y_px);
    if (!sample.valid || !std::isfinite(x_px) || !std::isfinite(y_px)) {
      target.gaze.push_back(std::nullopt);
      previous.reset();
      continue;
    }
    target.gaze.push_back(std::array<double, 2>{x_px, y_px});
    ++target.valid_samples;
    sum_x += x_px;
    sum_y += y_px;
    if (previous) {
      const double step_deg = eccentricity_deg(display, (*previous)[0], (*previous)[1], x_px, y_px);
      sum_squares += step_deg * step_deg;
      ++pairs;
    }
    previous = std::array<double, 2>{x_px, y_px};
  }
  if (target.valid_samples < 2 || 2 * target.valid_samples < target.samples || pairs == 0) return target;
  target.accuracy_deg =
      eccentricity_deg(display, target_x_px, target_y_px, sum_x / target.valid_samples, sum_y / target.valid_samples);
  target.precision_deg = std::sqrt(sum_squares / pairs);
  return target;
}

void summarise_validation(TrackerValidationEvent& attempt, const ValidationConfig& validation) {
  attempt.max_accuracy_deg = validation.max_accuracy_deg;
  attempt.max_precision_deg = validation.max_precision_deg;
  double accuracy = 0.0, precision = 0.0;
  bool complete = !attempt.targets.empty();
  for (const ValidationTarget& target : attempt.targets) {
    if (!target.accuracy_deg || !target.precision_deg) {
      complete = false;
      break;
    }
    accuracy += *target.accuracy_deg;
    precision += *target.precision_deg;
  }
  attempt.accuracy_deg.reset();
  attempt.precision_deg.reset();
  attempt.passed = false;
  if (!complete) return;
  const double count = static_cast<double>(attempt.targets.size());
  attempt.accuracy_deg = accuracy / count;
  attempt.precision_deg = precision / count;
  attempt.passed = !attempt.stopped && *attempt.accuracy_deg <= validation.max_accuracy_deg &&
                   *attempt.precision_deg <= validation.max_precision_deg;
}

}  // namespace fovlab
