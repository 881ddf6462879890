// Bruder et al. 2019's sampling mask (foveation/voronoi_mask.h): the weighted LBG reaches the equilibrium the
// authors' code reaches (for a 256x256 screen with s = 23 px: about 5,900 sites, under 5 % of the
// screen's pixels traced with the gaze at the centre, about 1.5 px between sites in the fovea and
// 7.5 px in the periphery), deterministically, in Morton order; its nearest-site cells are exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/prng.h"
#include "foveation/voronoi_mask.h"

namespace fovlab {
namespace {

VoronoiMaskSettings reference_settings() {
  VoronoiMaskSettings settings;
  settings.screen_width_px = 256;
  settings.screen_height_px = 256;
  settings.density_sigma_px = 23.0;
  return settings;
}

// Mean distance from each site within `radius` of (x, y) to its nearest other site.
double mean_spacing(const VoronoiMask& mask, double x, double y, double radius) {
  double sum = 0.0;
  int count = 0;
  for (size_t i = 0; i < mask.sites.size(); ++i) {
    const MaskSite& a = mask.sites[i];
    if (std::hypot(a.x_px - x, a.y_px - y) > radius) continue;
    double best = std::numeric_limits<double>::infinity();
    for (size_t j = 0; j < mask.sites.size(); ++j)
      if (j != i) best = std::min(best, double(std::hypot(a.x_px - mask.sites[j].x_px, a.y_px - mask.sites[j].y_px)));
    sum += best;
    ++count;
  }
  return count ? sum / count : 0.0;
}

int sites_within(const VoronoiMask& mask, double x0, double y0, double x1, double y1) {
  return int(std::count_if(mask.sites.begin(), mask.sites.end(), [&](const MaskSite& site) {
    return site.x_px >= x0 && site.x_px < x1 && site.y_px >= y0 && site.y_px < y1;
  }));
}

TEST(VoronoiMask, ReachesTheAuthorsEquilibriumFor256x256) {
  const VoronoiMask mask = make_voronoi_mask(reference_settings());
  EXPECT_EQ(mask.width_px, 512);
  EXPECT_EQ(mask.height_px, 512);
  EXPECT_TRUE(mask.converged);
  EXPECT_LE(mask.iterations, 64);
  const double sites = double(mask.sites.size());
  EXPECT_NEAR(sites, 5874.0, 0.03 * 5874.0);  // the authors' code: about 5,874
  // The screen is the mask's middle 256x256 with the gaze at the centre: under 8 % (the paper), about 4.5 %.
  const double screen_share = sites_within(mask, 128, 128, 384, 384) / (256.0 * 256.0);
  EXPECT_GT(screen_share, 0.04);
  EXPECT_LT(screen_share, 0.05);
  EXPECT_NEAR(mean_spacing(mask, 256, 256, 10), 1.55, 0.15);  // fovea
  EXPECT_NEAR(mean_spacing(mask, 40, 40, 30), 7.6, 0.4);      // periphery, at the floor of Phi
  // The equilibrium densities: 1/pi sites a pixel where Phi is 1 (d = 2 px), about 0.014 at the floor.
  EXPECT_NEAR(sites_within(mask, 251, 251, 261, 261) / 100.0, 1.0 / 3.14159, 0.06);
  EXPECT_NEAR(sites_within(mask, 0, 0, 96, 96) / (96.0 * 96.0), 0.0141, 0.003);
}

TEST(VoronoiMask, IsDeterministicAndSeeded) {
  VoronoiMaskSettings settings = reference_settings();
  settings.screen_width_px = 96;
  settings.screen_height_px = 64;
  settings.density_sigma_px = 9.0;
  settings.initial_sites = 2000;
  const VoronoiMask a = make_voronoi_mask(settings), b = make_voronoi_mask(settings);
  ASSERT_EQ(a.sites.size(), b.sites.size());
  for (size_t i = 0; i < a.sites.size(); ++i) {
    EXPECT_EQ(a.sites[i].x_px, b.sites[i].x_px);
    EXPECT_EQ(a.sites[i].y_px, b.sites[i].y_px);
  }
  settings.seed = 2;
  const VoronoiMask c = make_voronoi_mask(settings);
  EXPECT_NE(c.sites.front().x_px, a.sites.front().x_px);
  EXPECT_NEAR(double(c.sites.size()), double(a.sites.size()), 0.05 * double(a.sites.size()));
  // Every site lies on the mask, in Morton order.
  for (size_t i = 0; i < c.sites.size(); ++i) {
    const MaskSite& site = c.sites[i];
    ASSERT_TRUE(site.x_px >= 0 && site.x_px < 192 && site.y_px >= 0 && site.y_px < 128);
    if (i > 0) {
      const MaskSite& before = c.sites[i - 1];
      EXPECT_LE(morton_code(uint32_t(before.x_px), uint32_t(before.y_px)),
                morton_code(uint32_t(site.x_px), uint32_t(site.y_px)));
    }
  }
}

TEST(VoronoiMask, MortonCodeInterleavesXInTheEvenBits) {
  EXPECT_EQ(morton_code(0, 0), 0u);
  EXPECT_EQ(morton_code(1, 0), 1u);
  EXPECT_EQ(morton_code(0, 1), 2u);
  EXPECT_EQ(morton_code(3, 3), 15u);
  EXPECT_EQ(morton_code(4, 0), 16u);
  EXPECT_EQ(morton_code(0xffffffffu, 0), 0x5555555555555555ULL);
  EXPECT_EQ(morton_code(0, 0xffffffffu), 0xaaaaaaaaaaaaaaaaULL);
}

TEST(VoronoiMask, DensityIsTheQuantisedGaussianWithItsFloor) {
  const VoronoiMaskSettings settings = reference_settings();
  EXPECT_DOUBLE_EQ(mask_density(settings, 255, 255), 255.0 / 255.0);  // centre (256, 256) at 0.707 px: rounds to 1
  EXPECT_DOUBLE_EQ(mask_density(settings, 0, 0), 1.0 / 255.0);
  // Pixel (278, 255) has its centre 22.5 px right of and 0.5 px above the mask's centre (256, 256).
  EXPECT_DOUBLE_EQ(mask_density(settings, 278, 255) * 255.0,
                   std::round(255.0 * std::exp(-(22.5 * 22.5 + 0.5 * 0.5) / (2.0 * 23.0 * 23.0))));
}

// The nearest-site cells equal a brute-force search, ties going to the lower index.
TEST(VoronoiMask, NearestSitesAreExact) {
  Pcg32 random(7);
  std::vector<MaskSite> sites;
  for (int i = 0; i < 300; ++i) sites.push_back({float(random.uniform(0, 70)), float(random.uniform(0, 45))});
  sites.push_back(sites[10]);  // a duplicate: the lower index wins
  sites.push_back({35.5f, 22.5f});
  const std::vector<uint32_t> owner = nearest_sites(sites, 70, 45);
  for (int y = 0; y < 45; ++y)
    for (int x = 0; x < 70; ++x) {
      double best = 1e30;
      uint32_t best_index = 0;
      for (uint32_t i = 0; i < sites.size(); ++i) {
        const double d = std::pow(sites[i].x_px - (x + 0.5), 2) + std::pow(sites[i].y_px - (y + 0.5), 2);
        if (d < best) {
          best = d;
          best_index = i;
        }
      }
      ASSERT_EQ(owner[size_t(y) * 70 + size_t(x)], best_index) << x << "," << y;
    }
}

TEST(VoronoiMask, RefusesSettingsOutOfRange) {
  VoronoiMaskSettings settings = reference_settings();
  settings.density_sigma_px = 0.0;
  EXPECT_THROW(make_voronoi_mask(settings), std::invalid_argument);
  settings.density_sigma_px = std::nan("");
  EXPECT_THROW(make_voronoi_mask(settings), std::invalid_argument);
  settings = reference_settings();
  settings.screen_width_px = 0;
  EXPECT_THROW(make_voronoi_mask(settings), std::invalid_argument);
  settings = reference_settings();
  settings.initial_sites = 0;
  EXPECT_THROW(make_voronoi_mask(settings), std::invalid_argument);
  // A tiny screen and a huge radius still give a mask.
  settings = reference_settings();
  settings.screen_width_px = 1;
  settings.screen_height_px = 1;
  settings.density_sigma_px = 1e6;
  settings.initial_sites = 5;
  EXPECT_FALSE(make_voronoi_mask(settings).sites.empty());
}

}  // namespace
}  // namespace fovlab
