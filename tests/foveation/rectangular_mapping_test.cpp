// RMFR's rectangular mapping (Ye et al. 2022 eq. 3-7, the authors' signed form): fixed points, round trips
// to 1e-4 px, strict monotonicity, the density against finite differences of the map and its mean
// against the buffer's share of the screen, under gaze at every edge, off screen and NaN, sigma 1
// to 8 and focal shares near 0 and 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "foveation/rectangular_mapping.h"

namespace fovlab {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<RectangularMapping> stress_mappings() {
  std::vector<RectangularMapping> mappings;
  const int screens[][2] = {{1280, 720}, {257, 131}, {16, 9}};
  const double gazes[][2] = {{0.5, 0.5}, {0, 0}, {1, 1}, {0, 1}, {1, 0}, {0.3, 0.8}, {-2, 5}, {kNaN, kNaN}};
  for (const auto& screen : screens)
    for (const double sigma : {1.0, 1.4, 2.6, 8.0})
      for (const double focal : {1e-3, 0.05, 0.3, 0.8, 1.0})
        for (const auto& gaze : gazes)
          mappings.push_back(make_rectangular_mapping(screen[0], screen[1], sigma, focal,
                                                      std::clamp(1.001 - focal, 1e-3, 1.0), gaze[0] * screen[0],
                                                      gaze[1] * screen[1]));
  return mappings;
}

std::string describe(const RectangularMapping& m) {
  return std::to_string(m.screen_width_px) + "x" + std::to_string(m.screen_height_px) + " buffer " +
         std::to_string(m.buffer_width_px) + "x" + std::to_string(m.buffer_height_px) + " gaze share " +
         std::to_string(m.x.gaze_share) + "," + std::to_string(m.y.gaze_share) + " focal " +
         std::to_string(m.x.focal_share) + "," + std::to_string(m.y.focal_share);
}

TEST(RectangularMapping, BufferSizeAndTheoreticalSpeedup) {
  const RectangularMapping m = make_rectangular_mapping(1280, 720, 2.6, 0.3, 0.3, 640, 360);
  EXPECT_EQ(m.buffer_width_px, 492);                          // round(1280 / 2.6)
  EXPECT_EQ(m.buffer_height_px, 277);                         // round(720 / 2.6)
  EXPECT_NEAR(1.0 / m.theoretical_speedup(), 0.148, 0.0005);  // Ye et al. 2022: 14.8 % of the samples
  const RectangularMapping tiny = make_rectangular_mapping(5, 3, 8.0, 0.3, 0.3, 2, 1);
  EXPECT_EQ(tiny.buffer_width_px, 1);
  EXPECT_EQ(tiny.buffer_height_px, 1);
}

TEST(RectangularMapping, GazeIsClampedAndNaNIsTheCentre) {
  EXPECT_DOUBLE_EQ(rectangular_axis(0, 100, 0.3).gaze_share, kRmfrMinGazeShare);
  EXPECT_DOUBLE_EQ(rectangular_axis(-50, 100, 0.3).gaze_share, kRmfrMinGazeShare);
  EXPECT_DOUBLE_EQ(rectangular_axis(100, 100, 0.3).gaze_share, kRmfrMaxGazeShare);
  EXPECT_DOUBLE_EQ(rectangular_axis(kNaN, 100, 0.3).gaze_share, 0.5);
  EXPECT_DOUBLE_EQ(rectangular_axis(25, 100, 0.3).gaze_share, 0.25);
}

TEST(RectangularMapping, FixesTheEdgesAndTheGazeAndRoundTrips) {
  for (const RectangularMapping& m : stress_mappings()) {
    for (const RectangularAxis& axis : {m.x, m.y}) {
      EXPECT_NEAR(axis.to_buffer(0.0), 0.0, 1e-12) << describe(m);
      EXPECT_NEAR(axis.to_buffer(1.0), 1.0, 1e-12) << describe(m);
      EXPECT_NEAR(axis.to_buffer(axis.gaze_share), axis.gaze_share, 1e-12) << describe(m);
    }
    double previous_u = -1, previous_v = -1;
    const int steps = 97;
    for (int i = 0; i <= steps; ++i) {
      const double x = m.screen_width_px * double(i) / steps, y = m.screen_height_px * double(i) / steps;
      const auto [u, v] = m.to_buffer_px(x, y);
      ASSERT_TRUE(std::isfinite(u) && std::isfinite(v)) << describe(m) << " at " << i;
      EXPECT_GT(u, previous_u) << describe(m) << " at " << i;  // strictly increasing
      EXPECT_GT(v, previous_v) << describe(m) << " at " << i;
      previous_u = u;
      previous_v = v;
      const auto [x_again, y_again] = m.to_screen_px(u, v);
      EXPECT_NEAR(x_again, x, 1e-4) << describe(m) << " at " << i;
      EXPECT_NEAR(y_again, y, 1e-4) << describe(m) << " at " << i;
      // And from the buffer's side: every buffer position comes from a screen position.
      const double u_grid = m.buffer_width_px * double(i) / steps, v_grid = m.buffer_height_px * double(i) / steps;
      const auto [sx, sy] = m.to_screen_px(u_grid, v_grid);
      ASSERT_TRUE(std::isfinite(sx) && std::isfinite(sy)) << describe(m) << " at " << i;
      const auto [u_again, v_again] = m.to_buffer_px(sx, sy);
      EXPECT_NEAR(u_again, u_grid, 1e-4) << describe(m) << " at " << i;
      EXPECT_NEAR(v_again, v_grid, 1e-4) << describe(m) << " at " << i;
    }
  }
}

// The density is the map's derivative (checked by central differences, away from the gaze, where
// the two sides meet with different curvature), and its mean over the screen is the buffer's share
// of the screen's pixels: the shading pass's samples.
TEST(RectangularMapping, DensityIsTheDerivativeAndIntegratesToTheBufferShare) {
  for (const RectangularMapping& m : stress_mappings()) {
    for (const RectangularAxis& axis : {m.x, m.y}) {
      const double h = 1e-7;
      for (const double X : {0.001, 0.2, 0.45, 0.7, 0.999}) {
        if (std::abs(X - axis.gaze_share) < 1e-3) continue;
        const double numeric = (axis.to_buffer(X + h) - axis.to_buffer(X - h)) / (2 * h);
        EXPECT_NEAR(axis.density(X), numeric, 1e-4 * std::max(1.0, numeric)) << describe(m) << " at " << X;
      }
    }
    if (m.x.focal_share < 0.01 || m.y.focal_share < 0.01) continue;  // a spike too narrow for the sums below
    // Midpoint sums on a fine grid: each axis's mean density is 1, the 2-D mean the buffer's share.
    const int cells = 20000;
    double mean_x = 0, mean_y = 0;
    for (int i = 0; i < cells; ++i) {
      mean_x += m.x.density((i + 0.5) / cells) / cells;
      mean_y += m.y.density((i + 0.5) / cells) / cells;
    }
    EXPECT_NEAR(mean_x, 1.0, 2e-3) << describe(m);
    EXPECT_NEAR(mean_y, 1.0, 2e-3) << describe(m);
    const double share =
        double(m.buffer_width_px) * m.buffer_height_px / (double(m.screen_width_px) * m.screen_height_px);
    EXPECT_NEAR(mean_x * mean_y * share, 1.0 / m.theoretical_speedup(), 4e-3 * share) << describe(m);
  }
}

TEST(RectangularMapping, TheFoveaIsDenserThanThePeriphery) {
  const RectangularMapping m = make_rectangular_mapping(1280, 720, 2.6, 0.3, 0.3, 640, 360);
  EXPECT_GT(m.density(640, 360), 1.0);  // more than one sample a pixel at the gaze
  EXPECT_LT(m.density(0, 0), 0.05);     // far fewer in the corners
  EXPECT_GT(m.density(640, 360), m.density(900, 360));
  EXPECT_GT(m.density(900, 360), m.density(1279, 360));
}

TEST(RectangularMapping, SettingsOutOfRangeNameTheirField) {
  const auto field_of = [](auto make) -> std::string {
    try {
      make();
    } catch (const SettingError& error) {
      return error.field;
    }
    return "(none)";
  };
  EXPECT_EQ(field_of([] { make_rectangular_mapping(1280, 720, 0.5, 0.3, 0.3, 0, 0); }), "sigma");
  EXPECT_EQ(field_of([] { make_rectangular_mapping(1280, 720, 9.0, 0.3, 0.3, 0, 0); }), "sigma");
  EXPECT_EQ(field_of([] { make_rectangular_mapping(1280, 720, kNaN, 0.3, 0.3, 0, 0); }), "sigma");
  EXPECT_EQ(field_of([] { make_rectangular_mapping(1280, 720, 2.6, 0.0, 0.3, 0, 0); }), "focal_share_x");
  EXPECT_EQ(field_of([] { make_rectangular_mapping(1280, 720, 2.6, 0.3, 1.5, 0, 0); }), "focal_share_y");
  EXPECT_EQ(field_of([] { make_rectangular_mapping(0, 720, 2.6, 0.3, 0.3, 0, 0); }), "screen");
}

}  // namespace
}  // namespace fovlab
