#include "protocols/gaze/synthetic_gaze_source.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab {

namespace {

void require(bool condition, const std::string& what) {
  if (!condition) throw InputError("synthetic gaze: " + what);
}

}  // namespace

SyntheticGazeSource::SyntheticGazeSource(const SyntheticGazeParams& params, int width_px, int height_px)
    : params_(params), width_px_(width_px), height_px_(height_px), rng_(params.seed) {
  require(width_px > 0 && height_px > 0,
          "screen size must be positive, got " + std::to_string(width_px) + "x" + std::to_string(height_px));
  require(std::isfinite(params.fixation_min_s) && params.fixation_min_s > 0.0,
          "fixation_min_s must be > 0, got " + exact_number_text(params.fixation_min_s));
  require(std::isfinite(params.fixation_max_s) && params.fixation_max_s >= params.fixation_min_s,
          "fixation_max_s must be >= fixation_min_s, got " + exact_number_text(params.fixation_max_s));
  require(std::isfinite(params.saccade_s) && params.saccade_s >= 0.0,
          "saccade_s must be >= 0, got " + exact_number_text(params.saccade_s));
  require(std::isfinite(params.target_fraction) && params.target_fraction > 0.0 && params.target_fraction <= 1.0,
          "target_fraction must be in (0, 1], got " + exact_number_text(params.target_fraction));
  require(std::isfinite(params.jitter_sigma_fraction) && params.jitter_sigma_fraction >= 0.0,
          "jitter_sigma_fraction must be >= 0, got " + exact_number_text(params.jitter_sigma_fraction));
  require(std::isfinite(params.sample_age_ms) && params.sample_age_ms >= 0.0 && params.sample_age_ms <= 10000.0,
          "age_ms must be in [0, 10000], got " + exact_number_text(params.sample_age_ms));
  generate_next();
}

void SyntheticGazeSource::generate_next() {
  const double margin = 0.5 * (1.0 - params_.target_fraction);
  Fixation next;
  next.start_s = fixations_.empty() ? 0.0 : fixations_.back().end_s + params_.saccade_s;
  next.x_px = width_px_ * rng_.uniform(margin, 1.0 - margin);
  next.y_px = height_px_ * rng_.uniform(margin, 1.0 - margin);
  next.end_s = next.start_s + rng_.uniform(params_.fixation_min_s, params_.fixation_max_s);
  fixations_.push_back(next);
}

GazeSample SyntheticGazeSource::sample(double query_s) {
  if (!std::isfinite(query_s)) throw std::invalid_argument("SyntheticGazeSource::sample: time is not finite");
  // The sample read at query_s was taken sample_age_ms earlier: its position is the one of then.
  const double time_s = params_.sample_age_ms > 0.0 ? query_s - params_.sample_age_ms * 1e-3 : query_s;
  // The cache grows with t (about 2.3 fixations a second); a session time beyond 10^6 s is a bug.
  if (time_s > max_time_s) throw std::out_of_range("SyntheticGazeSource::sample: time beyond 10^6 s");
  // Generate until a fixation starts after time_s, so the one in use and the next target are known.
  while (fixations_.back().start_s <= time_s) generate_next();

  GazeSample sample;
  sample.time_s = query_s;
  sample.acquired_s = time_s;
  const auto add_jitter = [&] {
    if (params_.jitter_sigma_fraction <= 0.0) return;
    // A pure function of (seed, t): its own generator keyed by the bits of t.
    Pcg32 jitter(derive_seed(derive_seed(params_.seed, "jitter"), std::bit_cast<uint64_t>(time_s)));
    const double sigma = params_.jitter_sigma_fraction * width_px_;
    sample.x_px += sigma * jitter.normal();
    sample.y_px += sigma * jitter.normal();
  };
  if (target_px_) {
    sample.x_px = target_px_->first;
    sample.y_px = target_px_->second;
    add_jitter();
    return sample;
  }
  // Last fixation that started at or before time_s (the first one before t = 0).
  const auto later = std::upper_bound(fixations_.begin(), fixations_.end(), time_s,
                                      [](double t, const Fixation& f) { return t < f.start_s; });
  const Fixation& current = later == fixations_.begin() ? fixations_.front() : *(later - 1);
  if (time_s < current.end_s) {
    sample.x_px = current.x_px;
    sample.y_px = current.y_px;
    add_jitter();
  } else {
    // In the saccade from `current` to the next target (which exists: it starts after time_s).
    const Fixation& target = *later;
    const double progress = std::clamp((time_s - current.end_s) / params_.saccade_s, 0.0, 1.0);
    sample.x_px = current.x_px + progress * (target.x_px - current.x_px);
    sample.y_px = current.y_px + progress * (target.y_px - current.y_px);
  }
  return sample;
}

std::string SyntheticGazeSource::describe() const {
  std::string text = "synthetic:seed=" + std::to_string(params_.seed);
  if (params_.sample_age_ms > 0.0)
    text += ",age_ms=" + exact_number_text(params_.sample_age_ms);  // reads back the same
  return text;
}

}  // namespace fovlab
