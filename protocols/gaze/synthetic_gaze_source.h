#pragma once
// A seeded random fixation pattern (for pre-testing without an eye tracker): fixations at targets
// drawn uniformly over the central part of the screen, each held for a uniformly drawn duration,
// joined by saccades during which the gaze moves linearly (constant speed) to the next target.
//
// Timeline (session seconds): fixation 0 starts at t = 0; fixation i lasts d_i, then a saccade of
// saccade_s moves to target i+1, where fixation i+1 begins. Before t = 0 the gaze is at target 0.
// Draws come from one Pcg32 stream seeded with `seed`, per fixation in the order x, y, duration.
// Optional fixational jitter (gaussian, during fixations only) comes from a Pcg32 seeded with a
// hash of (seed, t), so it too depends on t alone.
//
// sample(t) is a pure function of (parameters, screen size, t): the fixation sequence is generated
// lazily in order and cached, so any order of queries (backwards too, or in another run) gives the
// same answer for the same t. Samples are always valid; time_s is the queried t.
//
// While a fixation target is set (set_fixation_target: an eye-tracker validation) the simulated
// participant looks at it exactly, with the fixational jitter when there is one; the fixation
// pattern above resumes, unchanged, when the target is cleared.
//
// sample_age_ms imitates a tracker's latency: the sample returned at t is the one taken at
// t - sample_age_ms (its position and its acquired_s), as a real tracker's latest sample is that old
// when the session reads it. 0 (the default): acquired_s = t, positions as without the option.
#include <cstdint>
#include <vector>

#include "core/prng.h"
#include "protocols/gaze/gaze_source.h"

namespace fovlab {

struct SyntheticGazeParams {
  double fixation_min_s = 0.2;  // fixation duration ~ uniform [min, max] (typical human fixations)
  double fixation_max_s = 0.6;
  double saccade_s = 0.03;             // duration of each saccade (>= 0; 0 = jumps)
  double target_fraction = 0.8;        // targets uniform over this central fraction of width and height
  double jitter_sigma_fraction = 0.0;  // fixational jitter sigma as a fraction of the width (0.001 typical)
  double sample_age_ms = 0.0;          // how old a sample is when it is read (0..10000 ms)
  uint64_t seed = 0;
};

class SyntheticGazeSource final : public GazeSource {
 public:
  // InputError when a parameter is out of range or the screen is empty.
  SyntheticGazeSource(const SyntheticGazeParams& params, int width_px, int height_px);

  // std::invalid_argument for a non-finite time, std::out_of_range beyond max_time_s.
  GazeSample sample(double time_s) override;
  std::string describe() const override;  // "synthetic:seed=<seed>", then ",age_ms=<ms>" when not 0
  void set_fixation_target(std::optional<std::pair<double, double>> target_px) override { target_px_ = target_px; }

  static constexpr double max_time_s = 1e6;  // the fixation cache grows with t

  const SyntheticGazeParams& params() const { return params_; }

 private:
  struct Fixation {
    double start_s;  // fixation begins (the previous saccade ended)
    double end_s;    // fixation ends, the saccade to the next target begins
    double x_px;
    double y_px;
  };
  void generate_next();

  SyntheticGazeParams params_;
  int width_px_;
  int height_px_;
  Pcg32 rng_;                        // the sequence stream, advanced only by generate_next()
  std::vector<Fixation> fixations_;  // generated so far, in order; never changed once generated
  std::optional<std::pair<double, double>> target_px_;
};

}  // namespace fovlab
