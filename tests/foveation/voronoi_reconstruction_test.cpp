// Natural-neighbour weights of the Voronoi sampling mask (foveation/voronoi_reconstruction.h):
// Sibson's coordinates have linear precision (they rebuild a point from its neighbours), a point on a
// site is that site, a point outside the hull takes its nearest site; every mask pixel's stored
// weights are complete and point at real sites; the disk cache gives back what was made and remakes
// a damaged file.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/prng.h"
#include "foveation/voronoi_reconstruction.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

std::vector<MaskSite> jittered_grid(int side, uint64_t seed) {
  Pcg32 random(seed);
  std::vector<MaskSite> sites;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      sites.push_back({float(10.0 * x + random.uniform(-3.0, 3.0)), float(10.0 * y + random.uniform(-3.0, 3.0))});
  return sites;
}

TEST(VoronoiReconstruction, SibsonCoordinatesHaveLinearPrecision) {
  const std::vector<MaskSite> sites = jittered_grid(8, 3);
  Pcg32 random(4);
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const double x = random.uniform(15.0, 55.0), y = random.uniform(15.0, 55.0);
    const auto weights = sibson_coordinates(sites, x, y);
    ASSERT_FALSE(weights.empty());
    double sum = 0.0, rebuilt_x = 0.0, rebuilt_y = 0.0;
    for (const auto& [site, weight] : weights) {
      EXPECT_GT(weight, 0.0);
      sum += weight;
      rebuilt_x += weight * sites[site].x_px;
      rebuilt_y += weight * sites[site].y_px;
    }
    EXPECT_NEAR(sum, 1.0, 1e-9);
    if (weights.size() < size_t(kVoronoiNeighbours)) {  // not truncated: exact linear precision
      EXPECT_NEAR(rebuilt_x, x, 1e-6);
      EXPECT_NEAR(rebuilt_y, y, 1e-6);
      ++checked;
    }
  }
  EXPECT_GT(checked, 150);
}

TEST(VoronoiReconstruction, SitesAndPointsOutsideTheHull) {
  const std::vector<MaskSite> sites = jittered_grid(5, 9);
  const auto on_site = sibson_coordinates(sites, sites[12].x_px, sites[12].y_px);
  ASSERT_EQ(on_site.size(), 1u);
  EXPECT_EQ(on_site[0].first, 12u);
  EXPECT_DOUBLE_EQ(on_site[0].second, 1.0);
  const auto outside = sibson_coordinates(sites, -100.0, -100.0);
  ASSERT_EQ(outside.size(), 1u);
  EXPECT_EQ(outside[0].first, 0u) << "the nearest site, the grid's corner";
  // Fewer than three sites: the nearest one.
  const auto two = sibson_coordinates({{0, 0}, {10, 0}}, 7.0, 1.0);
  ASSERT_EQ(two.size(), 1u);
  EXPECT_EQ(two[0].first, 1u);
}

VoronoiMaskSettings small_settings() {
  VoronoiMaskSettings settings;
  settings.screen_width_px = 24;
  settings.screen_height_px = 20;
  settings.density_sigma_px = 4.0;
  settings.initial_sites = 400;
  return settings;
}

TEST(VoronoiReconstruction, EveryMaskPixelHasCompleteWeights) {
  const VoronoiReconstruction r = make_voronoi_reconstruction(small_settings());
  ASSERT_EQ(r.mask.width_px, 48);
  ASSERT_EQ(r.mask.height_px, 40);
  ASSERT_EQ(r.neighbour_sites.size(), size_t(48 * 40 * kVoronoiNeighbours));
  for (size_t pixel = 0; pixel < size_t(48 * 40); ++pixel) {
    int sum = 0;
    for (int k = 0; k < kVoronoiNeighbours; ++k) {
      sum += r.neighbour_weights[pixel * kVoronoiNeighbours + size_t(k)];
      ASSERT_LT(r.neighbour_sites[pixel * kVoronoiNeighbours + size_t(k)], r.mask.sites.size());
    }
    ASSERT_NEAR(sum, 65535, kVoronoiNeighbours) << "pixel " << pixel;
  }
  EXPECT_GT(r.neighbour_reach_px, 0.5f);
  EXPECT_LT(r.neighbour_reach_px, 48.0f);
  // Pixel centres rebuilt from their neighbours' positions: within rounding inside the hull.
  const int x = 24, y = 20;
  double rebuilt_x = 0.0, rebuilt_y = 0.0;
  for (int k = 0; k < kVoronoiNeighbours; ++k) {
    const size_t entry = (size_t(y) * 48 + size_t(x)) * kVoronoiNeighbours + size_t(k);
    rebuilt_x += r.neighbour_weights[entry] / 65535.0 * r.mask.sites[r.neighbour_sites[entry]].x_px;
    rebuilt_y += r.neighbour_weights[entry] / 65535.0 * r.mask.sites[r.neighbour_sites[entry]].y_px;
  }
  EXPECT_NEAR(rebuilt_x, x + 0.5, 0.05);
  EXPECT_NEAR(rebuilt_y, y + 0.5, 0.05);
}

TEST(VoronoiReconstruction, CacheGivesBackWhatWasMadeAndRemakesADamagedFile) {
  testing::TempDir dir;
  bool made = false;
  double last_progress = -1.0;
  const VoronoiReconstruction first = cached_voronoi_reconstruction(
      small_settings(), dir.path(), [&](double share) { last_progress = share; }, &made);
  EXPECT_TRUE(made);
  EXPECT_EQ(last_progress, 1.0);
  const VoronoiReconstruction second = cached_voronoi_reconstruction(small_settings(), dir.path(), {}, &made);
  EXPECT_FALSE(made);
  EXPECT_EQ(second.neighbour_sites, first.neighbour_sites);
  EXPECT_EQ(second.neighbour_weights, first.neighbour_weights);
  ASSERT_EQ(second.mask.sites.size(), first.mask.sites.size());
  EXPECT_EQ(second.mask.sites[5].x_px, first.mask.sites[5].x_px);
  EXPECT_EQ(second.neighbour_reach_px, first.neighbour_reach_px);

  // Other settings: another file.
  VoronoiMaskSettings other = small_settings();
  other.seed = 2;
  cached_voronoi_reconstruction(other, dir.path(), {}, &made);
  EXPECT_TRUE(made);

  // A flipped byte: made anew (and right).
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    std::fstream file(entry.path(), std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(100);
    file.put('\x7f');
  }
  const VoronoiReconstruction third = cached_voronoi_reconstruction(small_settings(), dir.path(), {}, &made);
  EXPECT_TRUE(made);
  EXPECT_EQ(third.neighbour_weights, first.neighbour_weights);
}

}  // namespace
}  // namespace fovlab
