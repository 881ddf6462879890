#include "foveation/sampling_map.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "core/number_text.h"
#include "foveation/foveation_mask.h"

namespace fovlab {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

template <class Visit>
auto visit_map(const SamplingMap& map, Visit&& visit) {
  return std::visit(std::forward<Visit>(visit), map);
}

// The gaze on the screen: clamped to its pixels' extent, NaN taken at the centre.
double gaze_on_screen(double gaze_px, int screen_px) {
  return std::isnan(gaze_px) ? 0.5 * screen_px : std::clamp(gaze_px, 0.0, double(screen_px));
}

// The point `distance_px` from (x, y) along the line from the gaze through it (towards the gaze for
// a negative distance, stopping at the gaze): the nearest and farthest eccentricities within a
// disc around a point lie on that line, to first order.
std::pair<double, double> along_gaze_line(double gaze_x, double gaze_y, double x, double y, double distance_px) {
  const double dx = x - gaze_x, dy = y - gaze_y;
  const double length = std::hypot(dx, dy);
  if (length == 0.0) return {x + (distance_px > 0 ? distance_px : 0.0), y};
  const double scale = std::max(0.0, length + distance_px) / length;
  return {gaze_x + dx * scale, gaze_y + dy * scale};
}

// The box of screen points whose eccentricity is at most `radius_deg`, grown by `margin_px` and
// clipped to the screen: eccentricity grows along every ray from the gaze point on the display's
// plane, so its boundary is found by bisection along 128 rays. Empty (max < min) when no screen
// point is that close to the gaze.
struct Box {
  double min_x, min_y, max_x, max_y;
};
Box eccentricity_box(const DisplayGeometry& display, double gaze_x, double gaze_y, double radius_deg,
                     double margin_px) {
  const double far_px = 4.0 * double(display.width_px + display.height_px);
  Box box{gaze_x, gaze_y, gaze_x, gaze_y};
  constexpr int kRays = 128;
  for (int ray = 0; ray < kRays; ++ray) {
    const double angle = kTwoPi * ray / kRays;
    const double cx = std::cos(angle), cy = std::sin(angle);
    double inside = 0.0, outside = far_px;
    if (eccentricity_deg(display, gaze_x, gaze_y, gaze_x + cx * far_px, gaze_y + cy * far_px) <= radius_deg)
      inside = far_px;
    else
      for (int step = 0; step < 48; ++step) {
        const double middle = 0.5 * (inside + outside);
        (eccentricity_deg(display, gaze_x, gaze_y, gaze_x + cx * middle, gaze_y + cy * middle) <= radius_deg
             ? inside
             : outside) = middle;
      }
    box.min_x = std::min(box.min_x, gaze_x + cx * inside);
    box.max_x = std::max(box.max_x, gaze_x + cx * inside);
    box.min_y = std::min(box.min_y, gaze_y + cy * inside);
    box.max_y = std::max(box.max_y, gaze_y + cy * inside);
  }
  // Between two rays the boundary can bulge a little beyond the chord: a pixel more of margin.
  margin_px += 1.0;
  return Box{std::max(0.0, box.min_x - margin_px), std::max(0.0, box.min_y - margin_px),
             std::min(double(display.width_px), box.max_x + margin_px),
             std::min(double(display.height_px), box.max_y + margin_px)};
}

HyperbolicLayer layer_over(const Box& box, double pixel_size_px, double from_deg, double to_deg) {
  HyperbolicLayer layer;
  layer.pixel_size_px = pixel_size_px;
  layer.from_deg = from_deg;
  layer.to_deg = to_deg;
  if (box.max_x <= box.min_x || box.max_y <= box.min_y) return layer;  // off the screen: no samples
  layer.origin_x_px = std::floor(box.min_x / pixel_size_px) * pixel_size_px;
  layer.origin_y_px = std::floor(box.min_y / pixel_size_px) * pixel_size_px;
  layer.columns = int(std::ceil((box.max_x - layer.origin_x_px) / pixel_size_px));
  layer.rows = int(std::ceil((box.max_y - layer.origin_y_px) / pixel_size_px));
  return layer;
}

// Shares of the screen by eccentricity band, for the densities' means: over every pixel centre up
// to kExactBandPixels pixels (exact), over every stride-th pixel of each axis beyond (a session
// equalises once a gaze sample: 1280x720 then costs about 58,000 eccentricities, not 921,600).
constexpr int64_t kExactBandPixels = 65536;
struct BandAreas {
  double inside_inner = 0;   // e < r1
  double between = 0;        // r1 <= e < r2
  double between_ramp = 0;   // sum over those of (e - r1) / (r2 - r1)
  double outside_outer = 0;  // e >= r2
};
BandAreas band_areas(const DisplayGeometry& display, double gaze_x, double gaze_y, double r1_deg, double r2_deg) {
  const int64_t pixels = int64_t(display.width_px) * display.height_px;
  const int stride = pixels <= kExactBandPixels ? 1 : int(std::ceil(std::sqrt(double(pixels) / kExactBandPixels)));
  BandAreas areas;
  double count = 0;
  for (int y = stride / 2; y < display.height_px; y += stride)
    for (int x = stride / 2; x < display.width_px; x += stride) {
      const double e = eccentricity_deg(display, gaze_x, gaze_y, x + 0.5, y + 0.5);
      count += 1;
      if (e < r1_deg) areas.inside_inner += 1;
      else if (e < r2_deg) {
        areas.between += 1;
        areas.between_ramp += (e - r1_deg) / (r2_deg - r1_deg);
      } else areas.outside_outer += 1;
    }
  for (double* area : {&areas.inside_inner, &areas.between, &areas.between_ramp, &areas.outside_outer}) *area /= count;
  return areas;
}

uint64_t needed_samples(const HyperbolicLayers& layers, int layer) {
  uint64_t count = 0;
  for (int row = 0; row < layers.layers[size_t(layer)].rows; ++row)
    for (int column = 0; column < layers.layers[size_t(layer)].columns; ++column)
      count += layers.sample_needed(layer, column, row);
  return count;
}

// Equalise's solve for equal shaded samples: the parameter value in [low, high] whose count is
// nearest `target`, the count falling as the value rises (not strictly: counts are whole, and a
// buffer's size is rounded). Bisects for the crossing, then takes the nearer of its two ends.
template <class Count>
double nearest_to_target(double low, double high, uint64_t target, Count&& count) {
  for (int step = 0; step < 48; ++step) {
    const double middle = 0.5 * (low + high);
    (count(middle) >= target ? low : high) = middle;
  }
  const auto off_by = [&](double value) {
    const uint64_t n = count(value);
    return n > target ? n - target : target - n;
  };
  return off_by(low) <= off_by(high) ? low : high;
}

std::string samples_text(uint64_t count) { return std::to_string(count) + " shaded samples"; }

double mean_over_pixels(const SamplingMap& map) {
  const int width = screen_width_px(map), height = screen_height_px(map);
  double sum = 0.0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) sum += density(map, x + 0.5, y + 0.5);
  return sum / (double(width) * double(height));
}

}  // namespace

const char* resample_filter_name(ResampleFilter filter) {
  return filter == ResampleFilter::lanczos2 ? "lanczos" : "bilinear";
}

// --- KFR -----------------------------------------------------------------------------------------

std::pair<double, double> KernelLogPolarMapping::to_buffer_px(double x_px, double y_px) const {
  const double dx = x_px - gaze_x_px, dy = y_px - gaze_y_px;
  const double radius = std::hypot(dx, dy);
  const double log_share = std::clamp(std::log(std::max(radius, 1.0)) / log_max_radius, 0.0, 1.0);
  double angle = std::atan2(dy, dx);
  if (angle < 0) angle += kTwoPi;
  if (angle >= kTwoPi) angle = 0.0;  // a point a rounding error below the zero ray
  return {buffer_width_px * std::pow(log_share, alpha), buffer_height_px * angle / kTwoPi};
}

std::pair<double, double> KernelLogPolarMapping::to_screen_px(double u_px, double v_px) const {
  const double share = std::clamp(u_px / buffer_width_px, 0.0, 1.0);
  const double radius = std::exp(log_max_radius * std::pow(share, 1.0 / alpha));
  const double angle = kTwoPi * v_px / buffer_height_px;
  return {gaze_x_px + radius * std::cos(angle), gaze_y_px + radius * std::sin(angle)};
}

double KernelLogPolarMapping::density(double x_px, double y_px) const {
  const double radius = std::hypot(x_px - gaze_x_px, y_px - gaze_y_px);
  if (radius <= 1.0) return 0.0;
  const double log_share = std::log(radius) / log_max_radius;
  if (log_share >= 1.0) return 0.0;
  return double(buffer_width_px) * buffer_height_px * alpha * std::pow(log_share, alpha - 1.0) /
         (kTwoPi * log_max_radius * radius * radius);
}

std::pair<double, double> KernelLogPolarMapping::sample_spacings_px(double u_px) const {
  const double share = std::clamp(u_px / buffer_width_px, 1e-6, 1.0);
  const double radius = std::exp(log_max_radius * std::pow(share, 1.0 / alpha));
  const double dr_du = radius * log_max_radius * std::pow(share, 1.0 / alpha - 1.0) / (alpha * buffer_width_px);
  return {dr_du, kTwoPi * radius / buffer_height_px};
}

bool KernelLogPolarMapping::sample_shaded(int u, int v) const {
  const auto [x, y] = to_screen_px(u + 0.5, v + 0.5);
  const auto [radial, tangential] = sample_spacings_px(u + 0.5);
  const double margin = radial + tangential;
  return x >= -margin && x < screen_width_px + margin && y >= -margin && y < screen_height_px + margin;
}

KernelLogPolarMapping make_kernel_log_polar_mapping(int screen_width_px, int screen_height_px, double sigma,
                                                    double alpha, double gaze_x_px, double gaze_y_px) {
  check_screen_size(screen_width_px, screen_height_px);
  check_setting_range("sigma", sigma, kRmfrMinSigma, kRmfrMaxSigma);
  check_setting_range("alpha", alpha, kKfrMinAlpha, kKfrMaxAlpha);
  KernelLogPolarMapping mapping;
  mapping.screen_width_px = screen_width_px;
  mapping.screen_height_px = screen_height_px;
  mapping.buffer_width_px = reduced_buffer_px(screen_width_px, sigma);
  mapping.buffer_height_px = reduced_buffer_px(screen_height_px, sigma);
  mapping.sigma = sigma;
  mapping.alpha = alpha;
  mapping.gaze_x_px = gaze_on_screen(gaze_x_px, screen_width_px);
  mapping.gaze_y_px = gaze_on_screen(gaze_y_px, screen_height_px);
  double farthest = 0.0;
  for (double corner_x : {0.0, double(screen_width_px)})
    for (double corner_y : {0.0, double(screen_height_px)})
      farthest = std::max(farthest, std::hypot(corner_x - mapping.gaze_x_px, corner_y - mapping.gaze_y_px));
  mapping.log_max_radius = std::log(std::max(farthest, 2.0));
  return mapping;
}

// --- Hyperbolic -----------------------------------------------------------------------------------

std::array<double, 3> HyperbolicLayers::weights(double x_px, double y_px) const {
  const double e = eccentricity_deg(display, gaze_x_px, gaze_y_px, x_px, y_px);
  const auto fade = [&](double radius_deg) {
    if (blend_band_deg <= 0) return e < radius_deg ? 1.0 : 0.0;
    return std::clamp((radius_deg - e) / blend_band_deg, 0.0, 1.0);
  };
  const double inner = fade(inner_radius_deg);
  const double middle = (1.0 - inner) * fade(middle_radius_deg);
  return {inner, middle, 1.0 - inner - middle};
}

double HyperbolicLayers::density(double x_px, double y_px) const {
  const double e = eccentricity_deg(display, gaze_x_px, gaze_y_px, x_px, y_px);
  const HyperbolicLayer& layer = e < inner_radius_deg ? layers[0] : e < middle_radius_deg ? layers[1] : layers[2];
  return 1.0 / (layer.pixel_size_px * layer.pixel_size_px);
}

std::pair<double, double> HyperbolicLayers::sample_centre_px(int layer, int column, int row) const {
  const HyperbolicLayer& grid = layers[size_t(layer)];
  return {grid.origin_x_px + (column + 0.5) * grid.pixel_size_px, grid.origin_y_px + (row + 0.5) * grid.pixel_size_px};
}

bool HyperbolicLayers::sample_needed(int layer, int column, int row) const {
  const HyperbolicLayer& grid = layers[size_t(layer)];
  const auto [x, y] = sample_centre_px(layer, column, row);
  const double reach_px = 2.0 * grid.pixel_size_px;
  const auto [near_x, near_y] = along_gaze_line(gaze_x_px, gaze_y_px, x, y, -reach_px);
  const auto [far_x, far_y] = along_gaze_line(gaze_x_px, gaze_y_px, x, y, reach_px);
  return eccentricity_deg(display, gaze_x_px, gaze_y_px, near_x, near_y) <= grid.to_deg &&
         eccentricity_deg(display, gaze_x_px, gaze_y_px, far_x, far_y) >= grid.from_deg;
}

// --- Linear ---------------------------------------------------------------------------------------

double LinearFalloff::probability(double x_px, double y_px) const {
  return probability_at(eccentricity_deg(display, gaze_x_px, gaze_y_px, x_px, y_px));
}

double LinearFalloff::probability_at(double e) const {
  if (e <= inner_radius_deg) return 1.0;
  if (e >= outer_radius_deg) return min_probability;
  return 1.0 - (1.0 - min_probability) * (e - inner_radius_deg) / (outer_radius_deg - inner_radius_deg);
}

bool LinearFalloff::sampled(int x, int y) const {
  return mask_threshold(seed, 0, uint32_t(x), uint32_t(y)) < probability(x + 0.5, y + 0.5);
}

// --- The interface --------------------------------------------------------------------------------

int screen_width_px(const SamplingMap& map) {
  return visit_map(map, [](const auto& model) {
    if constexpr (requires { model.display; }) return model.display.width_px;
    else return model.screen_width_px;
  });
}

int screen_height_px(const SamplingMap& map) {
  return visit_map(map, [](const auto& model) {
    if constexpr (requires { model.display; }) return model.display.height_px;
    else return model.screen_height_px;
  });
}

double density(const SamplingMap& map, double x_px, double y_px) {
  if (const auto* linear = std::get_if<LinearFalloff>(&map)) return linear->probability(x_px, y_px);
  return visit_map(map, [&](const auto& model) {
    if constexpr (requires { model.density(x_px, y_px); }) return model.density(x_px, y_px);
    else return 0.0;
  });
}

double mean_density(const SamplingMap& map) {
  // RMFR's density is a product of per-axis densities, each of mean 1 over its axis: exact.
  if (const auto* rmfr = std::get_if<RectangularMapping>(&map)) return 1.0 / rmfr->theoretical_speedup();
  return mean_over_pixels(map);
}

uint64_t shaded_samples(const SamplingMap& map) {
  switch (model_of(map)) {
    case SamplingModel::rectangular: {
      const auto& rmfr = std::get<RectangularMapping>(map);
      return uint64_t(rmfr.buffer_width_px) * uint64_t(rmfr.buffer_height_px);
    }
    case SamplingModel::kernel_log_polar: {
      const auto& kfr = std::get<KernelLogPolarMapping>(map);
      uint64_t count = 0;
      for (int v = 0; v < kfr.buffer_height_px; ++v)
        for (int u = 0; u < kfr.buffer_width_px; ++u) count += kfr.sample_shaded(u, v);
      return count;
    }
    case SamplingModel::hyperbolic: {
      const auto& layers = std::get<HyperbolicLayers>(map);
      return needed_samples(layers, 0) + needed_samples(layers, 1) + needed_samples(layers, 2);
    }
    case SamplingModel::linear: {
      const auto& linear = std::get<LinearFalloff>(map);
      uint64_t count = 0;
      for (int y = 0; y < linear.display.height_px; ++y)
        for (int x = 0; x < linear.display.width_px; ++x) count += linear.sampled(x, y);
      return count;
    }
  }
  return 0;
}

double theoretical_speedup(const SamplingMap& map) {
  if (const auto* rmfr = std::get_if<RectangularMapping>(&map)) return rmfr->theoretical_speedup();
  if (const auto* kfr = std::get_if<KernelLogPolarMapping>(&map))
    return double(kfr->screen_width_px) * kfr->screen_height_px /
           (double(kfr->buffer_width_px) * kfr->buffer_height_px);
  return 1.0 / mean_density(map);
}

double effective_speedup(const SamplingMap& map) {
  const double screen = double(screen_width_px(map)) * double(screen_height_px(map));
  return screen / double(std::max<uint64_t>(1, shaded_samples(map)));
}

uint64_t rmfr_shaded_samples(int screen_width_px, int screen_height_px, double sigma) {
  return uint64_t(reduced_buffer_px(screen_width_px, sigma)) * uint64_t(reduced_buffer_px(screen_height_px, sigma));
}

const char* equalise_name(Equalise equalise) {
  switch (equalise) {
    case Equalise::off:
      return "off";
    case Equalise::samples:
      return "samples";
    case Equalise::density:
      return "density";
  }
  return "off";
}

namespace {

// KFR with its buffer's sigma solved so that it shades as many samples as RMFR at `sigma`: KFR's
// buffer is RMFR's size, but the part of it that falls off the screen is not shaded, so the solved
// sigma is smaller (Ye et al. 2022 compare the models at one sigma; the buffers, not the samples).
KernelLogPolarMapping kfr_with_equal_samples(const DisplayGeometry& display, double sigma, double alpha,
                                             double gaze_x_px, double gaze_y_px) {
  const uint64_t target = rmfr_shaded_samples(display.width_px, display.height_px, sigma);
  const auto make = [&](double buffer_sigma) {
    return make_kernel_log_polar_mapping(display.width_px, display.height_px, buffer_sigma, alpha, gaze_x_px,
                                         gaze_y_px);
  };
  const auto count = [&](double buffer_sigma) { return shaded_samples(SamplingMap(make(buffer_sigma))); };
  if (const uint64_t most = count(kRmfrMinSigma); most < target)
    throw InputError("equalise: the kfr model cannot reach RMFR's " + samples_text(target) + " at sigma " +
                     format_number(sigma, 4) + " on this display: with a buffer as large as the screen it shades " +
                     std::to_string(most) + " (raise sigma)");
  return make(nearest_to_target(kRmfrMinSigma, sigma, target, count));
}

// The linear model's p_min for as many shaded pixels as RMFR's samples at sigma: each pixel beyond
// r1 is shaded when its threshold lies below its probability, which rises with p_min, so the count
// does; the pixels' eccentricities and thresholds are taken once.
double linear_min_probability_for_samples(LinearFalloff linear, double sigma) {
  const DisplayGeometry& display = linear.display;
  const uint64_t target = rmfr_shaded_samples(display.width_px, display.height_px, sigma);
  uint64_t always = 0;  // within r1: probability 1, above every threshold
  std::vector<std::pair<double, double>> outside;  // (eccentricity, threshold) beyond r1
  for (int y = 0; y < display.height_px; ++y)
    for (int x = 0; x < display.width_px; ++x) {
      const double e = eccentricity_deg(display, linear.gaze_x_px, linear.gaze_y_px, x + 0.5, y + 0.5);
      if (e <= linear.inner_radius_deg) ++always;
      else outside.emplace_back(e, mask_threshold(linear.seed, 0, uint32_t(x), uint32_t(y)));
    }
  const auto count = [&](double p_min) {
    linear.min_probability = p_min;
    uint64_t n = always;
    for (const auto& [e, threshold] : outside) n += threshold < linear.probability_at(e);
    return n;
  };
  // The count rises with p_min: the solve's count falls as its value rises, so it runs on 1 - p_min.
  const auto count_of_complement = [&](double complement) { return count(1.0 - complement); };
  if (const uint64_t fewest = count(0.0); fewest > target)
    throw InputError("equalise: the linear model cannot reach RMFR's " + samples_text(target) + " at sigma " +
                     format_number(sigma, 4) + " on this display: with p_min 0 it shades " + std::to_string(fewest) +
                     " within " + format_number(linear.outer_radius_deg, 4) +
                     " deg alone (lower sigma, or the radii, or view the display from nearer)");
  return 1.0 - nearest_to_target(0.0, 1.0, target, count_of_complement);
}

}  // namespace

SamplingMap make_sampling_map(const SamplingSettings& settings, const DisplayGeometry& display, double gaze_x_px,
                              double gaze_y_px) {
  switch (settings.model) {
    case SamplingModel::rectangular:
      return make_rectangular_mapping(display.width_px, display.height_px, settings.sigma, settings.focal_share_x,
                                      settings.focal_share_y, gaze_x_px, gaze_y_px);
    case SamplingModel::kernel_log_polar:
      if (settings.equalise == Equalise::samples) {
        check_screen_size(display.width_px, display.height_px);
        check_setting_range("sigma", settings.sigma, kRmfrMinSigma, kRmfrMaxSigma);
        check_setting_range("alpha", settings.alpha, kKfrMinAlpha, kKfrMaxAlpha);
        return kfr_with_equal_samples(display, settings.sigma, settings.alpha, gaze_x_px, gaze_y_px);
      }
      return make_kernel_log_polar_mapping(display.width_px, display.height_px, settings.sigma, settings.alpha,
                                           gaze_x_px, gaze_y_px);
    case SamplingModel::hyperbolic:
    case SamplingModel::linear:
      break;
  }
  check_screen_size(display.width_px, display.height_px);
  if (!(display.width_mm > 0 && display.height_mm > 0 && display.viewing_distance_mm > 0))
    throw SettingError("display", ": expected a physical size and viewing distance (the " +
                                      std::string(sampling_model_name(settings.model)) +
                                      " model's radii are eccentricities)");
  check_setting_range("sigma", settings.sigma, kRmfrMinSigma, kRmfrMaxSigma);
  check_setting_range("inner_radius_deg", settings.inner_radius_deg, 0.0, 90.0);
  check_setting_range("outer_radius_deg", settings.outer_radius_deg, settings.inner_radius_deg, 90.0);
  const double gaze_x = gaze_on_screen(gaze_x_px, display.width_px);
  const double gaze_y = gaze_on_screen(gaze_y_px, display.height_px);
  const double target_density = 1.0 / (settings.sigma * settings.sigma);
  const std::string target_text = "1/sigma^2 = " + format_number(target_density, 4);

  if (settings.model == SamplingModel::linear) {
    check_setting_range("min_probability", settings.min_probability, 0.0, 1.0);
    if (settings.inner_radius_deg == 0.0 && settings.min_probability == 0.0 && settings.equalise == Equalise::off)
      throw SettingError("min_probability",
                         " 0: expected more than 0 when inner_radius_deg is 0 (no pixel would be shaded)");
    LinearFalloff linear{
        display,      gaze_x, gaze_y, settings.inner_radius_deg, settings.outer_radius_deg, settings.min_probability,
        settings.seed};
    if (settings.equalise == Equalise::samples) {
      linear.min_probability = linear_min_probability_for_samples(linear, settings.sigma);
    } else if (settings.equalise == Equalise::density) {
      // mean p = (inside + between - ramp + (ramp + outside) p_min) / pixels: linear in p_min.
      const BandAreas areas = band_areas(display, gaze_x, gaze_y, settings.inner_radius_deg, settings.outer_radius_deg);
      const double fixed = areas.inside_inner + areas.between - areas.between_ramp;
      const double per_p_min = areas.between_ramp + areas.outside_outer;
      const double p_min = per_p_min > 0 ? (target_density - fixed) / per_p_min : -1.0;
      if (!(p_min >= 0.0 && p_min <= 1.0))
        throw InputError("equalise: the linear model cannot reach " + target_text + " on this display: " +
                         (p_min > 1.0
                              ? "even p_min 1 gives less (raise sigma)"
                              : "with p_min 0 its density within " + format_number(settings.outer_radius_deg, 4) +
                                    " deg alone is " + format_number(fixed, 4) +
                                    " (lower sigma, or the radii, or view the display from nearer)"));
      linear.min_probability = p_min;
    }
    return linear;
  }

  check_setting_range("middle_pixel_size_px", settings.middle_pixel_size_px, 1.0, 64.0);
  if (settings.equalise == Equalise::off)  // else solved below
    check_setting_range("outer_pixel_size_px", settings.outer_pixel_size_px, settings.middle_pixel_size_px, 256.0);
  check_setting_range("blend_band_deg", settings.blend_band_deg, 0.0, settings.inner_radius_deg);
  double outer_pixel_size_px = settings.outer_pixel_size_px;
  if (settings.equalise == Equalise::density) {
    const BandAreas areas = band_areas(display, gaze_x, gaze_y, settings.inner_radius_deg, settings.outer_radius_deg);
    const double fixed =
        areas.inside_inner + areas.between / (settings.middle_pixel_size_px * settings.middle_pixel_size_px);
    const double left = target_density - fixed;
    const double size = left > 0 && areas.outside_outer > 0 ? std::sqrt(areas.outside_outer / left) : -1.0;
    if (!(size >= settings.middle_pixel_size_px && size <= 256.0)) {
      std::string why;
      if (areas.outside_outer <= 0)
        why =
            "no part of it lies beyond outer_radius_deg, so the outer pixel size changes nothing (lower "
            "outer_radius_deg)";
      else if (size > 256.0)
        why = "the outer pixel would be " + format_number(size, 4) + " px, more than 256 (lower sigma)";
      else if (size > 0)
        why = "the outer pixel would be " + format_number(size, 4) + " px, finer than the middle layer's " +
              format_number(settings.middle_pixel_size_px, 4) + " (raise sigma or middle_pixel_size_px)";
      else
        why = "its inner and middle layers alone give " + format_number(fixed, 4) +
              " (lower sigma, or the radii, or view the display from nearer)";
      throw InputError("equalise: the hyperbolic model cannot reach " + target_text + " on this display: " + why);
    }
    outer_pixel_size_px = size;
  }
  HyperbolicLayers layers;
  layers.display = display;
  layers.gaze_x_px = gaze_x;
  layers.gaze_y_px = gaze_y;
  layers.inner_radius_deg = settings.inner_radius_deg;
  layers.middle_radius_deg = settings.outer_radius_deg;
  layers.blend_band_deg = settings.blend_band_deg;
  const double band = settings.blend_band_deg;
  const Box inner_box = eccentricity_box(display, gaze_x, gaze_y, settings.inner_radius_deg, 2.0);
  const Box middle_box =
      eccentricity_box(display, gaze_x, gaze_y, settings.outer_radius_deg, 2.0 * settings.middle_pixel_size_px);
  const Box screen{0.0, 0.0, double(display.width_px), double(display.height_px)};
  const auto outer_layer = [&](double pixel_size_px) {
    return layer_over(screen, pixel_size_px, settings.outer_radius_deg - band, 180.0);
  };
  layers.layers = {layer_over(inner_box, 1.0, 0.0, settings.inner_radius_deg),
                   layer_over(middle_box, settings.middle_pixel_size_px, settings.inner_radius_deg - band,
                              settings.outer_radius_deg),
                   outer_layer(outer_pixel_size_px)};
  if (settings.equalise == Equalise::samples) {
    // The inner and middle layers' samples are fixed; the outer layer's fall as s3 grows.
    const uint64_t target = rmfr_shaded_samples(display.width_px, display.height_px, settings.sigma);
    const uint64_t fixed = needed_samples(layers, 0) + needed_samples(layers, 1);
    const auto count = [&](double pixel_size_px) {
      layers.layers[2] = outer_layer(pixel_size_px);
      return fixed + needed_samples(layers, 2);
    };
    const double finest = settings.middle_pixel_size_px, coarsest = 256.0;
    const uint64_t most = count(finest), fewest = count(coarsest);
    if (most < target || fewest > target) {
      std::string why;
      if (most == fewest)
        why = "no part of it lies beyond outer_radius_deg, so the outer pixel size changes nothing (lower "
              "outer_radius_deg)";
      else if (most < target)
        why = "even an outer pixel as fine as the middle layer's (" + format_number(finest, 4) + " px) shades " +
              std::to_string(most) + " (raise sigma or middle_pixel_size_px)";
      else if (fixed >= target)
        why = "its inner and middle layers alone shade " + std::to_string(fixed) +
              " (lower sigma, or the radii, or view the display from nearer)";
      else
        why = "an outer pixel of 256 px still shades " + std::to_string(fewest) + " (lower sigma)";
      throw InputError("equalise: the hyperbolic model cannot reach RMFR's " + samples_text(target) + " at sigma " +
                       format_number(settings.sigma, 4) + " on this display: " + why);
    }
    layers.layers[2] = outer_layer(nearest_to_target(finest, coarsest, target, count));
  }
  return layers;
}

SamplingSettings with_solved_equalise(SamplingSettings settings, const SamplingMap& solved) {
  if (settings.equalise == Equalise::off) return settings;
  if (const auto* layers = std::get_if<HyperbolicLayers>(&solved))
    settings.outer_pixel_size_px = layers->layers[2].pixel_size_px;
  if (const auto* linear = std::get_if<LinearFalloff>(&solved)) settings.min_probability = linear->min_probability;
  if (const auto* kfr = std::get_if<KernelLogPolarMapping>(&solved)) settings.sigma = kfr->sigma;
  settings.equalise = Equalise::off;
  return settings;
}

}  // namespace fovlab
