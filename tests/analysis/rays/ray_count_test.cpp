// Display geometry (pixel pitch, exact eccentricity) and the three-zone ray count of Polychronakis et al. 2021
// (section 5.1, Table 1): the convention that reproduces Table 1, the sorted table against a
// brute-force count, boundaries and degenerate zones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "analysis/rays/ray_count.h"
#include "core/input_error.h"
#include "foveation/display_geometry.h"

namespace {

using fovlab::DisplayGeometry;
using fovlab::InputError;
using fovlab::analysis::count_ray_grid;
using fovlab::analysis::count_rays;
using fovlab::analysis::EccentricityTable;
using fovlab::analysis::RayCell;

constexpr double kDegrees = 180.0 / std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Polychronakis et al. 2021, Table 1: speed-up for foveal zones (rows) and middle zones (columns), in degrees.
const std::vector<double> kFoveal = {5, 10, 15, 20, 25, 30};
const std::vector<double> kMiddle = {50, 55, 60, 65, 70, 75};
const double kTable1[6][6] = {{4.98, 4.56, 4.19, 3.95, 3.91, 3.91}, {4.60, 4.23, 3.91, 3.70, 3.67, 3.67},
                              {4.07, 3.78, 3.52, 3.35, 3.32, 3.32}, {3.49, 3.28, 3.08, 2.95, 2.93, 2.93},
                              {2.95, 2.79, 2.65, 2.55, 2.53, 2.53}, {2.47, 2.36, 2.25, 2.18, 2.17, 2.17}};

// The paper's set-up: 27" full HD at 50 cm, gaze at the centre.
DisplayGeometry paper_display() { return fovlab::display_from_diagonal(1920, 1080, 27.0, 500.0); }

// The ray from the eye to a point of the display, in millimetres (eye at the origin), written out
// independently of the code under test.
struct Vec {
  double x, y, z;
};
Vec eye_ray(const DisplayGeometry& d, double x_px, double y_px) {
  return {(x_px - d.width_px / 2.0) * d.width_mm / d.width_px, (y_px - d.height_px / 2.0) * d.height_mm / d.height_px,
          d.viewing_distance_mm};
}
double acos_angle_deg(const Vec& a, const Vec& b) {
  const double dot = a.x * b.x + a.y * b.y + a.z * b.z;
  const double norms = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z) * std::sqrt(b.x * b.x + b.y * b.y + b.z * b.z);
  return std::acos(std::clamp(dot / norms, -1.0, 1.0)) * kDegrees;
}

// The cell counted pixel by pixel, with the definition written out: pixel centre eccentricity
// <= angle / 2.
RayCell brute_force_cell(const DisplayGeometry& d, double gx, double gy, double foveal_deg, double middle_deg) {
  RayCell cell;
  for (int y = 0; y < d.height_px; ++y) {
    for (int x = 0; x < d.width_px; ++x) {
      const double e = fovlab::eccentricity_deg(d, gx, gy, x + 0.5, y + 0.5);
      if (e <= foveal_deg / 2) {
        ++cell.foveal_pixels;
      } else if (e <= middle_deg / 2) {
        ++cell.middle_pixels;
      } else {
        ++cell.outer_pixels;
      }
    }
  }
  return cell;
}

// Planar distance (mm) of every pixel centre from the display's centre, sorted.
std::vector<double> sorted_radii_mm(const DisplayGeometry& d) {
  std::vector<double> radii;
  for (int y = 0; y < d.height_px; ++y) {
    for (int x = 0; x < d.width_px; ++x) {
      const Vec r = eye_ray(d, x + 0.5, y + 0.5);
      radii.push_back(std::hypot(r.x, r.y));
    }
  }
  std::sort(radii.begin(), radii.end());
  return radii;
}

// Speed-ups of Table 1's grid when a zone of angle A is the disc of radius radius_mm(A) on the
// display around its centre (planar distance of the pixel centre, gaze at the centre).
template <typename Radius>
std::vector<double> planar_reading(const std::vector<double>& radii, Radius radius_mm) {
  const auto within = [&](double r) {
    return static_cast<double>(std::upper_bound(radii.begin(), radii.end(), r) - radii.begin());
  };
  const double n = static_cast<double>(radii.size());
  std::vector<double> speedups;
  for (double f : kFoveal) {
    for (double m : kMiddle) {
      const double foveal = within(radius_mm(f));
      const double middle = std::max(0.0, within(radius_mm(m)) - foveal);
      speedups.push_back(n / (foveal + middle / 4 + (n - foveal - middle) / 16));
    }
  }
  return speedups;
}

double max_error_against_table1(const std::vector<double>& speedups) {
  double worst = 0;
  for (size_t i = 0; i < speedups.size(); ++i) worst = std::max(worst, std::fabs(speedups[i] - kTable1[i / 6][i % 6]));
  return worst;
}

// ---------------------------------------------------------------------------------------------
// Display geometry

TEST(DisplayGeometry, TwentySevenInchFullHd) {
  const DisplayGeometry d = paper_display();
  EXPECT_EQ(d.width_px, 1920);
  EXPECT_EQ(d.height_px, 1080);
  EXPECT_NEAR(d.width_mm, 597.7, 0.05);
  EXPECT_NEAR(d.height_mm, 336.2, 0.05);
  EXPECT_DOUBLE_EQ(d.viewing_distance_mm, 500.0);
  EXPECT_NEAR(d.pixel_pitch_x_mm(), d.pixel_pitch_y_mm(), 1e-12);  // square pixels
  EXPECT_NEAR(std::hypot(d.width_mm, d.height_mm), 27 * 25.4, 1e-9);
  // About 28 pixels a degree at the centre (the derivative there): that many pixels right of the
  // centre lie atan(pi / 180) radians out, 0.9999 degrees.
  const double ppd = d.pixels_per_degree_at_centre();
  EXPECT_NEAR(ppd, 28.03, 0.01);
  EXPECT_NEAR(fovlab::eccentricity_deg(d, 960, 540, 960 + ppd, 540), std::atan(1 / kDegrees) * kDegrees, 1e-12);
}

TEST(DisplayGeometry, FromSizeKeepsTheValues) {
  const DisplayGeometry d = fovlab::display_from_size(640, 480, 320.0, 200.0, 700.0);
  EXPECT_EQ(d.width_px, 640);
  EXPECT_EQ(d.height_px, 480);
  EXPECT_DOUBLE_EQ(d.pixel_pitch_x_mm(), 0.5);
  EXPECT_DOUBLE_EQ(d.pixel_pitch_y_mm(), 200.0 / 480);
}

TEST(DisplayGeometry, BadValuesThrowInputError) {
  EXPECT_THROW(fovlab::display_from_diagonal(0, 1080, 27, 500), InputError);
  EXPECT_THROW(fovlab::display_from_diagonal(1920, -1, 27, 500), InputError);
  EXPECT_THROW(fovlab::display_from_diagonal(1920, 1080, 0, 500), InputError);
  EXPECT_THROW(fovlab::display_from_diagonal(1920, 1080, -27, 500), InputError);
  EXPECT_THROW(fovlab::display_from_diagonal(1920, 1080, kNaN, 500), InputError);
  EXPECT_THROW(fovlab::display_from_diagonal(1920, 1080, kInf, 500), InputError);
  EXPECT_THROW(fovlab::display_from_diagonal(1920, 1080, 27, 0), InputError);
  EXPECT_THROW(fovlab::display_from_diagonal(1920, 1080, 27, -500), InputError);
  EXPECT_THROW(fovlab::display_from_diagonal(1920, 1080, 27, kNaN), InputError);
  EXPECT_THROW(fovlab::display_from_size(1920, 1080, 0, 300, 500), InputError);
  EXPECT_THROW(fovlab::display_from_size(1920, 1080, 500, -300, 500), InputError);
  EXPECT_THROW(fovlab::display_from_size(1920, 1080, kInf, 300, 500), InputError);
  EXPECT_THROW(fovlab::display_from_size(1920, 1080, 500, 300, 0), InputError);
  EXPECT_THROW(fovlab::display_from_size(0, 0, 500, 300, 500), InputError);
}

TEST(Eccentricity, ZeroAtTheGazePoint) {
  const DisplayGeometry d = paper_display();
  for (const auto& [gx, gy] : std::vector<std::pair<double, double>>{
           {960, 540}, {0, 0}, {12.5, 1000.25}, {1919.5, 0.5}, {-3000, 5000}, {1e7, -1e7}}) {
    EXPECT_EQ(fovlab::eccentricity_deg(d, gx, gy, gx, gy), 0.0) << gx << "," << gy;
  }
}

TEST(Eccentricity, GazeAtTheCentreIsAtanOfDistanceOverViewingDistance) {
  const DisplayGeometry d = paper_display();
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{
           {961, 540}, {0.5, 0.5}, {1919.5, 1079.5}, {960, 0}, {100, 900}, {-5000, 540}, {960, 1e6}}) {
    const Vec r = eye_ray(d, x, y);
    const double expected = std::atan(std::hypot(r.x, r.y) / d.viewing_distance_mm) * kDegrees;
    EXPECT_NEAR(fovlab::eccentricity_deg(d, 960, 540, x, y), expected, 1e-10) << x << "," << y;
  }
  // The corner of the paper's display: atan(342.9 / 500), the half-diagonal being 13.5".
  EXPECT_NEAR(fovlab::eccentricity_deg(d, 960, 540, 0, 0), std::atan(13.5 * 25.4 / 500) * kDegrees, 1e-10);
}

TEST(Eccentricity, SymmetricInGazeAndPoint) {
  const DisplayGeometry d = fovlab::display_from_size(800, 600, 400, 250, 450);
  const std::vector<std::pair<double, double>> points = {{0, 0}, {400, 300}, {799.5, 10.5}, {-200, 700}, {3000, -50}};
  for (const auto& [ax, ay] : points) {
    for (const auto& [bx, by] : points) {
      EXPECT_NEAR(fovlab::eccentricity_deg(d, ax, ay, bx, by), fovlab::eccentricity_deg(d, bx, by, ax, ay), 1e-12);
    }
  }
  // Mirror images about the centre lines lie at the same eccentricity from the centre.
  EXPECT_EQ(fovlab::eccentricity_deg(d, 400, 300, 10.5, 20.5), fovlab::eccentricity_deg(d, 400, 300, 789.5, 579.5));
}

TEST(Eccentricity, OffCentreGazeMatchesTheAcosFormula) {
  const DisplayGeometry d = fovlab::display_from_size(1000, 700, 520, 300, 600);
  const std::vector<std::pair<double, double>> gazes = {{0, 0}, {999, 350}, {123.4, 654.3}, {-800, -900}};
  const std::vector<std::pair<double, double>> points = {{500, 350}, {10, 690}, {990.5, 0.5}, {4000, 2000}, {-1e5, 3}};
  for (const auto& [gx, gy] : gazes) {
    for (const auto& [x, y] : points) {
      const double expected = acos_angle_deg(eye_ray(d, gx, gy), eye_ray(d, x, y));
      // acos is ill-conditioned near 0 and 180 degrees; these angles are well inside.
      EXPECT_NEAR(fovlab::eccentricity_deg(d, gx, gy, x, y), expected, 1e-9) << gx << "," << gy << " " << x << "," << y;
    }
  }
}

TEST(Eccentricity, SmallAnglesKeepTheirDigits) {
  // One millionth of a pixel from the gaze point: atan2 gives the angle to full relative precision;
  // the acos form would return 0 or noise here.
  const DisplayGeometry d = paper_display();
  const double dx_px = (960 + 1e-6) - 960;  // the offset the function is given, exactly
  const double expected = std::atan(dx_px * d.pixel_pitch_x_mm() / d.viewing_distance_mm) * kDegrees;
  EXPECT_NEAR(fovlab::eccentricity_deg(d, 960, 540, 960 + dx_px, 540) / expected, 1.0, 1e-9);
}

TEST(Eccentricity, FarOffScreenApproachesNinetyDegrees) {
  const DisplayGeometry d = paper_display();
  for (double far : {1e6, 1e12, 1e100, 1e200}) {
    for (const auto& [x, y] : std::vector<std::pair<double, double>>{{far, 540}, {960, -far}, {-far, far}}) {
      const double e = fovlab::eccentricity_deg(d, 960, 540, x, y);
      EXPECT_FALSE(std::isnan(e)) << x << "," << y;
      EXPECT_LE(e, 90.0);
      EXPECT_GT(e, 89.9);
    }
  }
  // Off-centre gaze, both far away on opposite sides: the angle tends to 180 and stays below it.
  const double e = fovlab::eccentricity_deg(d, -1e200, 540, 1e200, 540);
  EXPECT_FALSE(std::isnan(e));
  EXPECT_LE(e, 180.0);
  EXPECT_GT(e, 179.9);
}

// ---------------------------------------------------------------------------------------------
// Ray counts

TEST(RayCount, ReproducesTable1OfPolychronakis2021) {
  const std::vector<RayCell> cells = count_ray_grid(paper_display(), 960, 540, kFoveal, kMiddle);
  ASSERT_EQ(cells.size(), 36u);
  double worst = 0;
  int truncated_matches = 0;
  for (size_t i = 0; i < cells.size(); ++i) {
    const RayCell& cell = cells[i];
    EXPECT_EQ(cell.foveal_deg, kFoveal[i / 6]);
    EXPECT_EQ(cell.middle_deg, kMiddle[i % 6]);
    EXPECT_EQ(cell.foveal_pixels + cell.middle_pixels + cell.outer_pixels, 1920 * 1080);
    EXPECT_DOUBLE_EQ(cell.rays, cell.foveal_pixels + cell.middle_pixels / 4.0 + cell.outer_pixels / 16.0);
    EXPECT_DOUBLE_EQ(cell.speedup, 1920.0 * 1080.0 / cell.rays);
    EXPECT_NEAR(cell.speedup, kTable1[i / 6][i % 6], 0.02)
        << "foveal " << cell.foveal_deg << ", middle " << cell.middle_deg;
    worst = std::max(worst, std::fabs(cell.speedup - kTable1[i / 6][i % 6]));
    truncated_matches += std::floor(cell.speedup * 100) == std::round(kTable1[i / 6][i % 6] * 100);
  }
  EXPECT_LT(worst, 0.01);
  // The paper's values look truncated to two decimals: 34 of the 36 cells are (the 30-degree row's
  // 2.4674 and 2.3584 are printed 2.47 and 2.36).
  EXPECT_EQ(truncated_matches, 34);
  // The paper's text: 15/65 is "over 3x", 30/75 "at least 2x".
  EXPECT_GT(cells[2 * 6 + 3].speedup, 3.0);
  EXPECT_GT(cells[5 * 6 + 5].speedup, 2.0);
}

TEST(RayCount, OtherReadingsOfTheZoneAngleMissTable1) {
  const DisplayGeometry d = paper_display();
  const double distance = d.viewing_distance_mm;
  const std::vector<double> radii = sorted_radii_mm(d);
  const auto radians = [](double deg) { return deg / kDegrees; };
  // The convention, as a disc on the screen (gaze at the centre): radius D tan(A / 2).
  const double half =
      max_error_against_table1(planar_reading(radii, [&](double a) { return distance * std::tan(radians(a / 2)); }));
  EXPECT_LT(half, 0.01);
  // A read as the zone's radius (eccentricity <= A): radius D tan(A).
  const double radius =
      max_error_against_table1(planar_reading(radii, [&](double a) { return distance * std::tan(radians(a)); }));
  EXPECT_NEAR(radius, 1.90, 0.01);
  // Equation 4 read literally (2 arctan(d / 2D) <= A): radius 2 D tan(A / 2).
  const double eq4 = max_error_against_table1(
      planar_reading(radii, [&](double a) { return 2 * distance * std::tan(radians(a / 2)); }));
  EXPECT_NEAR(eq4, 1.86, 0.01);
  // The first other reading through the library: exact eccentricity <= A.
  const EccentricityTable table(d, 960, 540);
  std::vector<double> doubled;
  for (double f : kFoveal) {
    for (double m : kMiddle) doubled.push_back(count_rays(table, 2 * f, 2 * m).speedup);
  }
  EXPECT_NEAR(max_error_against_table1(doubled), radius, 1e-9);
}

TEST(RayCount, SortedTableMatchesBruteForce) {
  struct Case {
    DisplayGeometry display;
    double gx, gy;
  };
  const DisplayGeometry even = fovlab::display_from_size(40, 24, 120, 72, 90);   // 3 mm pixels, wide angles
  const DisplayGeometry odd = fovlab::display_from_diagonal(37, 23, 4.0, 60);    // odd sizes: a centre pixel
  const DisplayGeometry oblong = fovlab::display_from_size(31, 16, 40, 50, 35);  // non-square pixels
  const std::vector<Case> cases = {{even, 20, 12},  {even, 0, 0},      {even, 40, 24},    {even, 17.5, 3.5},
                                   {even, -30, 50}, {even, 200, -100}, {odd, 18.5, 11.5}, {odd, 0, 23},
                                   {odd, 60, 11.5}, {oblong, 15.5, 8}, {oblong, 31, 0},   {oblong, -5, -5}};
  for (const Case& c : cases) {
    const EccentricityTable table(c.display, c.gx, c.gy);
    ASSERT_EQ(table.pixel_count(), int64_t{c.display.width_px} * c.display.height_px);
    // Angles: fixed ones, and twice the eccentricity of some pixel centres, so those pixels lie
    // exactly on a zone's bound.
    std::vector<double> angles = {0, 1, 5, 10, 20, 45, 90, 120, 179, 360};
    for (const auto& [x, y] : std::vector<std::pair<int, int>>{{0, 0}, {3, 2}, {c.display.width_px - 1, 5}, {10, 10}}) {
      angles.push_back(2 * fovlab::eccentricity_deg(c.display, c.gx, c.gy, x + 0.5, y + 0.5));
    }
    for (double foveal : angles) {
      for (double middle : angles) {
        const RayCell fast = count_rays(table, foveal, middle);
        const RayCell slow = brute_force_cell(c.display, c.gx, c.gy, foveal, middle);
        EXPECT_EQ(fast.foveal_pixels, slow.foveal_pixels) << c.gx << "," << c.gy << " " << foveal << "/" << middle;
        EXPECT_EQ(fast.middle_pixels, slow.middle_pixels) << c.gx << "," << c.gy << " " << foveal << "/" << middle;
        EXPECT_EQ(fast.outer_pixels, slow.outer_pixels) << c.gx << "," << c.gy << " " << foveal << "/" << middle;
      }
    }
  }
}

TEST(RayCount, PixelExactlyOnTheBoundIsInside) {
  const DisplayGeometry d = fovlab::display_from_size(40, 24, 120, 72, 90);
  const EccentricityTable table(d, 20, 12);  // gaze on the corner shared by four pixels
  // Pixel (25, 12): its centre's eccentricity, and its three mirror images share it exactly.
  const double bound = fovlab::eccentricity_deg(d, 20, 12, 25.5, 12.5);
  const int64_t inside = table.pixels_within(bound);
  const int64_t below = table.pixels_within(std::nextafter(bound, 0.0));
  EXPECT_GE(inside - below, 4);
  EXPECT_EQ(count_rays(table, 2 * bound, 2 * bound).foveal_pixels, inside);
  EXPECT_EQ(count_rays(table, std::nextafter(2 * bound, 0.0), 2 * bound).middle_pixels, inside - below);
}

TEST(RayCount, ZonesCoveringTheWholeScreen) {
  const DisplayGeometry d = fovlab::display_from_size(64, 36, 600, 340, 500);
  const EccentricityTable table(d, 32, 18);
  // The corner is ~37.7 degrees out: a 76-degree foveal zone holds every pixel.
  const RayCell all_foveal = count_rays(table, 76, 100);
  EXPECT_EQ(all_foveal.foveal_pixels, 64 * 36);
  EXPECT_EQ(all_foveal.middle_pixels, 0);
  EXPECT_EQ(all_foveal.outer_pixels, 0);
  EXPECT_EQ(all_foveal.speedup, 1.0);
  EXPECT_EQ(count_rays(table, 360, 360).speedup, 1.0);
  // The middle zone holds everything: 4x.
  EXPECT_EQ(count_rays(table, 0, 360).speedup, 4.0);
}

TEST(RayCount, EmptyZones) {
  // Even sizes, gaze at the centre: no pixel centre lies at eccentricity 0, so zero-degree zones
  // hold nothing and every pixel costs 1/16 of a ray.
  const DisplayGeometry even = fovlab::display_from_size(64, 36, 600, 340, 500);
  const RayCell nothing = count_rays(EccentricityTable(even, 32, 18), 0, 0);
  EXPECT_EQ(nothing.foveal_pixels, 0);
  EXPECT_EQ(nothing.middle_pixels, 0);
  EXPECT_EQ(nothing.outer_pixels, 64 * 36);
  EXPECT_EQ(nothing.speedup, 16.0);
  // Gaze on a pixel centre: a zero-degree foveal zone holds exactly that pixel.
  const RayCell one = count_rays(EccentricityTable(even, 10.5, 20.5), 0, 0);
  EXPECT_EQ(one.foveal_pixels, 1);
  EXPECT_EQ(one.middle_pixels, 0);
  // Gaze far off the screen: zones of 30 degrees reach no pixel.
  EXPECT_EQ(count_rays(EccentricityTable(even, 5000, 18), 30, 60).speedup, 16.0);
}

TEST(RayCount, MiddleSmallerThanFovealIsEmpty) {
  const EccentricityTable table(paper_display(), 960, 540);
  const RayCell smaller = count_rays(table, 30, 10);
  const RayCell equal = count_rays(table, 30, 30);
  EXPECT_EQ(smaller.middle_pixels, 0);
  EXPECT_EQ(smaller.foveal_pixels, equal.foveal_pixels);
  EXPECT_EQ(smaller.outer_pixels, equal.outer_pixels);
  EXPECT_EQ(smaller.speedup, equal.speedup);
  EXPECT_GT(smaller.foveal_pixels, 0);
}

TEST(RayCount, GridIsFovealMajor) {
  const std::vector<RayCell> cells = count_ray_grid(paper_display(), 100, 100, {5, 10}, {20, 40, 60});
  ASSERT_EQ(cells.size(), 6u);
  for (size_t i = 0; i < cells.size(); ++i) {
    EXPECT_EQ(cells[i].foveal_deg, i < 3 ? 5 : 10);
    EXPECT_EQ(cells[i].middle_deg, std::vector<double>({20, 40, 60})[i % 3]);
  }
  // Larger zones cost more rays.
  EXPECT_GT(cells[0].speedup, cells[1].speedup);
  EXPECT_GT(cells[1].speedup, cells[2].speedup);
  EXPECT_GT(cells[0].speedup, cells[3].speedup);
  EXPECT_TRUE(count_ray_grid(paper_display(), 960, 540, {}, {50}).empty());
}

TEST(RayCount, BadInputThrowsInputError) {
  const DisplayGeometry d = fovlab::display_from_size(16, 9, 160, 90, 300);
  const EccentricityTable table(d, 8, 4.5);
  EXPECT_THROW(count_rays(table, -1, 10), InputError);
  EXPECT_THROW(count_rays(table, 5, -0.5), InputError);
  EXPECT_THROW(count_rays(table, kNaN, 10), InputError);
  EXPECT_THROW(count_rays(table, 5, kInf), InputError);
  EXPECT_THROW(count_ray_grid(d, 8, 4.5, {5, -5}, {10}), InputError);
  EXPECT_THROW(count_ray_grid(d, 8, 4.5, {5}, {kNaN}), InputError);
  EXPECT_THROW(EccentricityTable(d, kNaN, 4), InputError);
  EXPECT_THROW(EccentricityTable(d, 8, kInf), InputError);
  EXPECT_THROW(EccentricityTable(DisplayGeometry{0, 9, 160, 90, 300}, 8, 4), InputError);
}

}  // namespace
