#include "foveation/voronoi_mask.h"

#include <algorithm>
#include <numbers>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "core/prng.h"

namespace fovlab {

namespace {

// Sites bucketed on a square grid, for nearest-site queries by rings of cells.
class SiteGrid {
 public:
  SiteGrid(const std::vector<MaskSite>& sites, int width_px, int height_px) : sites_(sites) {
    // About two sites a cell on average.
    const double area = double(width_px) * double(height_px);
    cell_px_ = std::max(2.0, std::sqrt(2.0 * area / double(std::max<size_t>(sites.size(), 1))));
    columns_ = std::max(1, int(std::ceil(width_px / cell_px_)));
    rows_ = std::max(1, int(std::ceil(height_px / cell_px_)));
    std::vector<uint32_t> counts(size_t(columns_) * size_t(rows_) + 1, 0);
    for (const MaskSite& site : sites) ++counts[cell_of(site.x_px, site.y_px) + 1];
    std::partial_sum(counts.begin(), counts.end(), counts.begin());
    first_ = counts;
    members_.resize(sites.size());
    std::vector<uint32_t> next(counts.begin(), counts.end() - 1);
    for (uint32_t i = 0; i < sites.size(); ++i) members_[next[cell_of(sites[i].x_px, sites[i].y_px)]++] = i;
  }

  // The nearest site to (x, y) (ties: the lower index).
  uint32_t nearest(double x, double y) const {
    const int cx = std::clamp(int(x / cell_px_), 0, columns_ - 1), cy = std::clamp(int(y / cell_px_), 0, rows_ - 1);
    double best = std::numeric_limits<double>::infinity();
    uint32_t best_index = 0;
    const int max_ring = std::max(columns_, rows_);
    for (int ring = 0; ring <= max_ring; ++ring) {
      for (int gy = cy - ring; gy <= cy + ring; ++gy) {
        if (gy < 0 || gy >= rows_) continue;
        const bool edge_row = gy == cy - ring || gy == cy + ring;
        for (int gx = cx - ring; gx <= cx + ring; gx += (edge_row || ring == 0) ? 1 : 2 * ring) {
          if (gx < 0 || gx >= columns_) continue;
          const size_t cell = size_t(gy) * size_t(columns_) + size_t(gx);
          for (uint32_t k = first_[cell]; k < first_[cell + 1]; ++k) {
            const uint32_t index = members_[k];
            const double dx = sites_[index].x_px - x, dy = sites_[index].y_px - y;
            const double d2 = dx * dx + dy * dy;
            if (d2 < best || (d2 == best && index < best_index)) {
              best = d2;
              best_index = index;
            }
          }
        }
      }
      // Cells beyond this ring lie at least ring * cell_px_ away.
      const double reach = ring * cell_px_;
      if (best <= reach * reach) break;
    }
    return best_index;
  }

 private:
  size_t cell_of(float x, float y) const {
    const int gx = std::clamp(int(x / cell_px_), 0, columns_ - 1), gy = std::clamp(int(y / cell_px_), 0, rows_ - 1);
    return size_t(gy) * size_t(columns_) + size_t(gx);
  }
  const std::vector<MaskSite>& sites_;
  double cell_px_ = 1.0;
  int columns_ = 1, rows_ = 1;
  std::vector<uint32_t> first_, members_;
};

// What one iteration gathers over a site's cell.
struct CellMoments {
  uint32_t pixels = 0;
  double mass = 0.0;                                      // T_r
  double x = 0.0, y = 0.0, xx = 0.0, xy = 0.0, yy = 0.0;  // Phi-weighted sums
};

void check_settings(const VoronoiMaskSettings& settings) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("voronoi mask: " + what); };
  if (settings.screen_width_px < 1 || settings.screen_height_px < 1 || settings.screen_width_px > 4096 ||
      settings.screen_height_px > 4096)
    fail("expected a screen of 1 to 4096 pixels a side (the mask is twice that)");
  if (!(settings.density_sigma_px > 0.0 && std::isfinite(settings.density_sigma_px)))
    fail("expected a positive, finite density radius");
  if (settings.initial_sites < 1 || settings.initial_sites > 1000000) fail("expected 1 to 10^6 initial sites");
  if (settings.max_iterations < 1 || settings.max_iterations > 1000) fail("expected 1 to 1000 iterations");
  if (!(settings.hysteresis_start >= 0.0 && settings.hysteresis_step >= 0.0 &&
        std::isfinite(settings.hysteresis_start) && std::isfinite(settings.hysteresis_step)))
    fail("expected a hysteresis that is finite and not negative");
}

float inside(double value, int size) { return float(std::clamp(value, 1e-3, double(size) - 1e-3)); }

}  // namespace

VoronoiMaskSettings voronoi_mask_settings(int width_px, int height_px, const DisplayGeometry& display,
                                          double sigma_deg) {
  VoronoiMaskSettings settings;
  settings.screen_width_px = width_px;
  settings.screen_height_px = height_px;
  settings.density_sigma_px = density_sigma_px(display, sigma_deg);
  return settings;
}

double density_sigma_px(const DisplayGeometry& display, double sigma_deg) {
  return sigma_deg * display.pixels_per_degree_at_centre();
}

double mask_density(const VoronoiMaskSettings& settings, int x_px, int y_px) {
  const double dx = x_px + 0.5 - settings.screen_width_px, dy = y_px + 0.5 - settings.screen_height_px;
  const double s = settings.density_sigma_px;
  const double phi = std::exp(-(dx * dx + dy * dy) / (2.0 * s * s));
  return std::max(1.0, std::round(phi * 255.0)) / 255.0;
}

uint64_t morton_code(uint32_t x, uint32_t y) {
  const auto spread = [](uint64_t v) {
    v &= 0xffffffffULL;
    v = (v | (v << 16)) & 0x0000ffff0000ffffULL;
    v = (v | (v << 8)) & 0x00ff00ff00ff00ffULL;
    v = (v | (v << 4)) & 0x0f0f0f0f0f0f0f0fULL;
    v = (v | (v << 2)) & 0x3333333333333333ULL;
    v = (v | (v << 1)) & 0x5555555555555555ULL;
    return v;
  };
  return spread(x) | (spread(y) << 1);
}

std::vector<uint32_t> nearest_sites(const std::vector<MaskSite>& sites, int width_px, int height_px) {
  if (sites.empty()) throw std::invalid_argument("nearest_sites: no site");
  const SiteGrid grid(sites, width_px, height_px);
  std::vector<uint32_t> owner(size_t(width_px) * size_t(height_px));
  for (int y = 0; y < height_px; ++y)
    for (int x = 0; x < width_px; ++x) owner[size_t(y) * size_t(width_px) + size_t(x)] = grid.nearest(x + 0.5, y + 0.5);
  return owner;
}

VoronoiMask make_voronoi_mask(const VoronoiMaskSettings& settings) {
  check_settings(settings);
  VoronoiMask mask;
  mask.width_px = 2 * settings.screen_width_px;
  mask.height_px = 2 * settings.screen_height_px;
  const int width = mask.width_px, height = mask.height_px;
  std::vector<double> phi(size_t(width) * size_t(height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) phi[size_t(y) * size_t(width) + size_t(x)] = mask_density(settings, x, y);

  Pcg32 random(derive_seed(settings.seed, "voronoi_mask"));
  std::vector<MaskSite> sites(size_t(settings.initial_sites));
  for (MaskSite& site : sites) {
    site.x_px = inside(random.uniform(0.0, width), width);
    site.y_px = inside(random.uniform(0.0, height), height);
  }

  for (int iteration = 0; iteration < settings.max_iterations && !mask.converged; ++iteration) {
    const std::vector<uint32_t> owner = nearest_sites(sites, width, height);
    std::vector<CellMoments> cells(sites.size());
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const size_t p = size_t(y) * size_t(width) + size_t(x);
        CellMoments& cell = cells[owner[p]];
        const double w = phi[p], px = x + 0.5, py = y + 0.5;
        ++cell.pixels;
        cell.mass += w;
        cell.x += w * px;
        cell.y += w * py;
        cell.xx += w * px * px;
        cell.xy += w * px * py;
        cell.yy += w * py * py;
      }
    }
    const double hysteresis = settings.hysteresis_start + iteration * settings.hysteresis_step;
    std::vector<MaskSite> next;
    next.reserve(sites.size() + sites.size() / 4);
    bool changed = false;
    for (const CellMoments& cell : cells) {
      if (cell.pixels == 0) {  // a site that owns no pixel stands for nothing
        changed = true;
        continue;
      }
      const double diameter = 0.5 + 1.5 * std::sqrt(cell.mass / cell.pixels);
      const double area = std::numbers::pi * diameter * diameter / 4.0;
      if (cell.mass < area * (1.0 - hysteresis / 2.0)) {
        changed = true;
        continue;
      }
      const double cx = cell.x / cell.mass, cy = cell.y / cell.mass;
      if (cell.mass <= area * (1.0 + hysteresis / 2.0)) {
        next.push_back({inside(cx, width), inside(cy, height)});
        continue;
      }
      // Split along the principal axis of the cell's Phi-weighted spread.
      const double vxx = cell.xx / cell.mass - cx * cx, vyy = cell.yy / cell.mass - cy * cy;
      const double vxy = cell.xy / cell.mass - cx * cy;
      const double angle = 0.5 * std::atan2(2.0 * vxy, vxx - vyy);
      const double offset = 0.5 * std::sqrt(cell.pixels / std::numbers::pi);
      const double ox = offset * std::cos(angle), oy = offset * std::sin(angle);
      next.push_back({inside(cx - ox, width), inside(cy - oy, height)});
      next.push_back({inside(cx + ox, width), inside(cy + oy, height)});
      changed = true;
    }
    if (next.empty()) {  // every cell was smaller than its site's area (a tiny mask): one site stays
      const auto largest = std::max_element(cells.begin(), cells.end(),
                                            [](const CellMoments& a, const CellMoments& b) { return a.mass < b.mass; });
      next.push_back({inside(largest->x / largest->mass, width), inside(largest->y / largest->mass, height)});
    }
    sites = std::move(next);
    mask.iterations = iteration + 1;
    mask.converged = !changed;
  }

  // Morton order of the sites' pixels (ties keep the order the iterations left them in).
  std::vector<uint64_t> codes(sites.size());
  for (size_t i = 0; i < sites.size(); ++i) codes[i] = morton_code(uint32_t(sites[i].x_px), uint32_t(sites[i].y_px));
  std::vector<size_t> order(sites.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return codes[a] < codes[b]; });
  mask.sites.reserve(sites.size());
  for (size_t i : order) mask.sites.push_back(sites[i]);
  return mask;
}

}  // namespace fovlab
