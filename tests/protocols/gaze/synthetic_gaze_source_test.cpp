#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "core/prng.h"
#include "protocols/gaze/synthetic_gaze_source.h"

namespace fovlab {
namespace {

constexpr int width = 1920;
constexpr int height = 1080;

SyntheticGazeParams seeded(uint64_t seed) {
  SyntheticGazeParams params;
  params.seed = seed;
  return params;
}

TEST(GazeSynthetic, FirstFixationFollowsTheDocumentedDraws) {
  SyntheticGazeSource source(seeded(1234), width, height);
  EXPECT_EQ(source.describe(), "synthetic:seed=1234");
  Pcg32 rng(1234);  // per fixation: x, y, duration
  const double x = width * rng.uniform(0.1, 0.9);
  const double y = height * rng.uniform(0.1, 0.9);
  const double duration = rng.uniform(0.2, 0.6);
  for (const double t : {-5.0, 0.0, duration * 0.5, duration - 1e-9}) {
    const GazeSample sample = source.sample(t);
    EXPECT_TRUE(sample.valid);
    EXPECT_DOUBLE_EQ(sample.time_s, t);
    EXPECT_DOUBLE_EQ(sample.x_px, x);
    EXPECT_DOUBLE_EQ(sample.y_px, y);
  }
  // Halfway through the first saccade: halfway to the second target.
  const double x2 = width * rng.uniform(0.1, 0.9);
  const double y2 = height * rng.uniform(0.1, 0.9);
  const GazeSample mid = source.sample(duration + 0.015);
  EXPECT_NEAR(mid.x_px, 0.5 * (x + x2), 1e-6);
  EXPECT_NEAR(mid.y_px, 0.5 * (y + y2), 1e-6);
  const GazeSample arrived = source.sample(duration + 0.03 + 1e-9);
  EXPECT_DOUBLE_EQ(arrived.x_px, x2);
  EXPECT_DOUBLE_EQ(arrived.y_px, y2);
}

TEST(GazeSynthetic, SameAnswerForTheSameTimeInAnyQueryOrder) {
  std::vector<double> times;
  for (int i = 0; i < 3000; ++i) times.push_back(i * 0.01);  // 30 s
  std::vector<double> shuffled = times;
  Pcg32 order(99);
  order.shuffle(shuffled);

  SyntheticGazeSource forward(seeded(42), width, height);
  std::vector<GazeSample> expected;
  for (const double t : times) expected.push_back(forward.sample(t));

  SyntheticGazeSource random_order(seeded(42), width, height);
  for (const double t : shuffled) {
    const GazeSample sample = random_order.sample(t);
    const GazeSample& reference = expected[static_cast<size_t>(std::lround(t / 0.01))];
    ASSERT_EQ(sample.x_px, reference.x_px) << "t = " << t;
    ASSERT_EQ(sample.y_px, reference.y_px) << "t = " << t;
  }
  // A fresh source asked for a late time first ("after a restart") and then backwards.
  SyntheticGazeSource late_first(seeded(42), width, height);
  for (size_t i = times.size(); i-- > 0;) {
    ASSERT_EQ(late_first.sample(times[i]).x_px, expected[i].x_px) << "t = " << times[i];
  }
  // Another seed gives another pattern.
  SyntheticGazeSource other(seeded(43), width, height);
  int same = 0;
  for (size_t i = 0; i < times.size(); i += 10) same += other.sample(times[i]).x_px == expected[i].x_px;
  EXPECT_LT(same, 5);
}

TEST(GazeSynthetic, FixationsSaccadesAndTargetsHaveTheConfiguredShape) {
  SyntheticGazeSource source(seeded(7), width, height);
  constexpr double dt = 0.001;
  constexpr int steps = 60000;  // 60 s
  struct Run {
    bool moving;
    int length;  // samples
  };
  std::vector<Run> runs;
  std::vector<double> fixation_x;
  std::vector<double> fixation_y;
  GazeSample previous = source.sample(0.0);
  fixation_x.push_back(previous.x_px);
  fixation_y.push_back(previous.y_px);
  runs.push_back({false, 1});
  std::vector<double> saccade_steps;  // step lengths of the current saccade
  int saccades_checked = 0;
  for (int i = 1; i < steps; ++i) {
    const GazeSample sample = source.sample(i * dt);
    const double step = std::hypot(sample.x_px - previous.x_px, sample.y_px - previous.y_px);
    const bool moving = step > 0.0;
    if (moving) saccade_steps.push_back(step);
    if (!moving && runs.back().moving) {
      fixation_x.push_back(sample.x_px);
      fixation_y.push_back(sample.y_px);
      // Constant speed: every whole step of a saccade is as long as the others (the first and the
      // last are cut by the step grid).
      for (size_t k = 2; k + 1 < saccade_steps.size(); ++k) {
        ASSERT_NEAR(saccade_steps[k], saccade_steps[1], 1e-6 * std::max(1.0, saccade_steps[1])) << "t = " << i * dt;
      }
      saccades_checked += saccade_steps.size() > 20;
      saccade_steps.clear();
    }
    if (moving == runs.back().moving) {
      ++runs.back().length;
    } else {
      runs.push_back({moving, 1});
    }
    previous = sample;
  }
  EXPECT_GT(saccades_checked, 100);

  // Complete runs only (not the last one, cut by the end of the scan).
  double fixation_sum = 0.0;
  int fixation_count = 0;
  for (size_t i = 0; i + 1 < runs.size(); ++i) {
    const double duration = runs[i].length * dt;
    if (runs[i].moving) {
      // The saccade of 0.03 s: its last step lands on the target, so the moving run covers
      // 29 or 30 steps of 1 ms (30 when the step grid meets the fixation start exactly).
      EXPECT_GE(duration, 0.03 - 1.5 * dt) << "run " << i;
      EXPECT_LE(duration, 0.03 + 1.5 * dt) << "run " << i;
    } else {
      EXPECT_GE(duration, 0.2 - 1.5 * dt) << "run " << i;
      EXPECT_LE(duration, 0.6 + 1.5 * dt) << "run " << i;
      fixation_sum += duration;
      ++fixation_count;
    }
  }
  ASSERT_GT(fixation_count, 100);  // about 60 / 0.43
  ASSERT_LT(fixation_count, 200);
  EXPECT_NEAR(fixation_sum / fixation_count, 0.4 + dt, 0.04);

  // Targets: inside the central 80 %, spread over it.
  double min_x = width, max_x = 0, min_y = height, max_y = 0, sum_x = 0;
  for (size_t i = 0; i < fixation_x.size(); ++i) {
    min_x = std::min(min_x, fixation_x[i]);
    max_x = std::max(max_x, fixation_x[i]);
    min_y = std::min(min_y, fixation_y[i]);
    max_y = std::max(max_y, fixation_y[i]);
    sum_x += fixation_x[i];
  }
  EXPECT_GE(min_x, 0.1 * width);
  EXPECT_LE(max_x, 0.9 * width);
  EXPECT_GE(min_y, 0.1 * height);
  EXPECT_LE(max_y, 0.9 * height);
  EXPECT_LT(min_x, 0.2 * width);
  EXPECT_GT(max_x, 0.8 * width);
  EXPECT_LT(min_y, 0.2 * height);
  EXPECT_GT(max_y, 0.8 * height);
  EXPECT_NEAR(sum_x / fixation_x.size(), 0.5 * width, 0.08 * width);
}

TEST(GazeSynthetic, JitterIsSmallGaussianAndRepeatable) {
  SyntheticGazeParams params = seeded(5);
  params.fixation_min_s = params.fixation_max_s = 10.0;  // one long fixation
  params.jitter_sigma_fraction = 0.001;                  // 1.92 px
  SyntheticGazeSource jittered(params, width, height);
  params.jitter_sigma_fraction = 0.0;
  SyntheticGazeSource still(params, width, height);

  const double centre_x = still.sample(1.0).x_px;
  double sum = 0.0;
  double sum_squares = 0.0;
  constexpr int count = 4000;
  for (int i = 0; i < count; ++i) {
    const double t = 0.001 + i * 0.002;
    const double x = jittered.sample(t).x_px;
    ASSERT_EQ(jittered.sample(t).x_px, x);  // same t, same answer
    const double offset = x - centre_x;
    sum += offset;
    sum_squares += offset * offset;
  }
  const double mean = sum / count;
  const double sigma = std::sqrt(sum_squares / count - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.15);
  EXPECT_NEAR(sigma, 1.92, 0.15);
}

TEST(GazeSynthetic, BadParametersAndTimes) {
  SyntheticGazeParams params;
  params.fixation_min_s = 0.0;
  EXPECT_THROW(SyntheticGazeSource(params, width, height), InputError);
  params = {};
  params.fixation_max_s = 0.1;  // below the minimum
  EXPECT_THROW(SyntheticGazeSource(params, width, height), InputError);
  params = {};
  params.target_fraction = 1.5;
  EXPECT_THROW(SyntheticGazeSource(params, width, height), InputError);
  params = {};
  EXPECT_THROW(SyntheticGazeSource(params, 0, height), InputError);

  SyntheticGazeSource source(seeded(1), width, height);
  EXPECT_THROW(source.sample(std::nan("")), std::invalid_argument);
  EXPECT_THROW(source.sample(2e6), std::out_of_range);
}

}  // namespace
}  // namespace fovlab
