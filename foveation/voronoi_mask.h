#pragma once
// Bruder et al. 2019's sampling mask (Bruder et al. 2019, section 4.1): where a foveated volume raycaster
// starts its rays. A mask of 2W x 2H pixels, twice the screen per axis, centred on the gaze (it is
// shifted with the gaze by whole pixels), holds sites placed by the weighted Linde-Buzo-Gray
// algorithm (Deussen et al. 2017) so that their density follows
//   Phi(m) = max(exp(-|m - c|^2 / (2 s^2)), 1/255),
// stored with 8 bits as the authors' code stores it (c the mask's centre, s about 2.5 degrees of
// visual angle in pixels: density_sigma_px). Each iteration assigns every mask pixel to its nearest
// site (its Voronoi cell V_r) and compares the cell's integral T_r = sum of Phi over V_r with the area
// a site should stand for there, A_r = pi d_r^2 / 4 with d_r = 0.5 + 1.5 sqrt(T_r / |V_r|) pixels
// (the authors' code; the paper leaves it open), under the hysteresis h_i = 0.5 + 0.1 i (the paper's
// epsilon_0 and epsilon_Delta):
//   T_r <  A_r (1 - h_i / 2): the site is deleted;
//   T_r <= A_r (1 + h_i / 2): it moves to the Phi-weighted centroid of its cell;
//   otherwise it is split in two along the cell's principal axis, at centroid +- 0.5 sqrt(|V_r| / pi).
// A mask so small that every cell falls short keeps one site (the heaviest cell's centroid).
// It starts from 10,000 sites uniformly at random (core/prng.h, seeded: the same settings give the
// same mask on every machine) and stops when an iteration neither splits nor deletes, or after 64.
// The sites are then sorted in Morton order (x in the even bits, y in the odd), so that rays traced
// in list order stay close on the screen.
#include <cstdint>
#include <vector>

#include "foveation/display_geometry.h"

namespace fovlab {

struct VoronoiMaskSettings {
  int screen_width_px = 256;  // the mask is twice this per axis
  int screen_height_px = 256;
  double density_sigma_px = 32.0;  // s: Phi's Gaussian radius, in mask (= screen) pixels
  int initial_sites = 10000;
  int max_iterations = 64;
  double hysteresis_start = 0.5;  // epsilon_0
  double hysteresis_step = 0.1;   // epsilon_Delta (the authors' code used 0.01)
  uint64_t seed = 1;
};

// The Gaussian radius s of 2.5 degrees of visual angle (Bruder et al. 2019's choice) on `display`, in pixels
// at its centre.
double density_sigma_px(const DisplayGeometry& display, double sigma_deg = 2.5);

struct MaskSite {
  float x_px, y_px;  // in mask pixels (pixel (i, j) covers [i, i + 1) x [j, j + 1))
};

struct VoronoiMask {
  int width_px = 0, height_px = 0;  // 2W x 2H
  std::vector<MaskSite> sites;      // in Morton order
  int iterations = 0;               // iterations run
  bool converged = false;           // the last neither split nor deleted
};

// The settings of a mask for a screen of width_px x height_px pixels on `display`, with the Gaussian
// radius sigma_deg (degrees of visual angle, at the display's centre) and the other settings at their
// defaults.
VoronoiMaskSettings voronoi_mask_settings(int width_px, int height_px, const DisplayGeometry& display,
                                          double sigma_deg = 2.5);

// Phi at a mask pixel's centre, quantised to 8 bits (at least 1/255).
double mask_density(const VoronoiMaskSettings& settings, int x_px, int y_px);

// Runs the weighted LBG. std::invalid_argument on sizes under 1 or over 8192 a side, a radius that
// is not positive and finite, or counts out of range (1 to 10^6 initial sites, 1 to 1000 iterations).
VoronoiMask make_voronoi_mask(const VoronoiMaskSettings& settings);

// The Morton code of a pixel: x in the even bits, y in the odd bits.
uint64_t morton_code(uint32_t x, uint32_t y);

// For each mask pixel, the index of its nearest site (ties: the lower index): the Voronoi cells as the
// algorithm sees them. Row-major, width_px x height_px.
std::vector<uint32_t> nearest_sites(const std::vector<MaskSite>& sites, int width_px, int height_px);

}  // namespace fovlab
