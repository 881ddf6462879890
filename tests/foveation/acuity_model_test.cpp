// foveation/acuity_model.h: Polychronakis et al. 2021 eq. 1-2 with the outer periphery.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "foveation/acuity_model.h"

namespace fovlab {
namespace {

TEST(AcuityModel, TheFitFallsFromItsValueAtZeroToItsFloor) {
  EXPECT_DOUBLE_EQ(acuity_fit(0.0), 0.90964 + 0.00792);
  // One scale length: the exponential part is 1/e of its start.
  EXPECT_NEAR(acuity_fit(2.9661), 0.90964 / std::exp(1.0) + 0.00792, 1e-15);
  EXPECT_NEAR(acuity_fit(5.0), 0.1764870625367, 1e-12);  // 0.90964 e^(-5 / 2.9661) + 0.00792 (Python)
  EXPECT_NEAR(acuity_fit(90.0), 0.00792, 1e-12);
  for (double w = 0.0; w < 60.0; w += 0.5) EXPECT_LT(acuity_fit(w + 0.5), acuity_fit(w)) << w;
}

TEST(AcuityModel, ProbabilityIsOneInTheFoveaTheFitInThePeripheryAndZeroBeyond) {
  const AcuityModel model{7.5, 40.0};
  EXPECT_EQ(model.trace_probability(0.0), 1.0);
  EXPECT_EQ(model.trace_probability(7.5), 1.0);  // the boundary belongs to the fovea
  EXPECT_DOUBLE_EQ(model.trace_probability(7.5001), acuity_fit(7.5001));
  EXPECT_DOUBLE_EQ(model.trace_probability(40.0), acuity_fit(40.0));
  EXPECT_EQ(model.trace_probability(40.0001), 0.0);
  EXPECT_EQ(model.trace_probability(179.0), 0.0);
}

TEST(AcuityModel, UndefinedEccentricitiesAreTracedInFull) {
  const AcuityModel model{5.0};
  EXPECT_EQ(model.trace_probability(std::numeric_limits<double>::quiet_NaN()), 1.0);
  EXPECT_EQ(model.trace_probability(-3.0), 1.0);
  EXPECT_GT(model.trace_probability(std::numeric_limits<double>::infinity()), 0.0);  // no outer zone: the floor
  const AcuityModel no_fovea{0.0};
  EXPECT_EQ(no_fovea.trace_probability(0.0), 1.0);  // the gaze point itself
  EXPECT_DOUBLE_EQ(no_fovea.trace_probability(1e-9), acuity_fit(1e-9));
}

}  // namespace
}  // namespace fovlab
