#include "metrics/image_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "metrics/image_checks.h"

namespace fovlab::metrics {
namespace {

using detail::colour_channel_count;
using detail::require_same_size;
using detail::require_valid_layout;
using detail::size_text;

// BT.601 luma weights, as MATLAB's rgb2gray (used by Wang et al.'s code).
constexpr double kLumaRed = 0.299;
constexpr double kLumaGreen = 0.587;
constexpr double kLumaBlue = 0.114;

// SSIM constants of Wang et al. 2004, section III-C, for data range L = 1.
constexpr double kDataRange = 1.0;
constexpr double kK1 = 0.01;
constexpr double kK2 = 0.03;
constexpr double kC1 = (kK1 * kDataRange) * (kK1 * kDataRange);
constexpr double kC2 = (kK2 * kDataRange) * (kK2 * kDataRange);
constexpr int kWindowSize = 11;
constexpr double kWindowSigma = 1.5;

constexpr double kPsnrPeak = 1.0;

// Number of channels that carry colour: alpha is not part of the picture.

// Luma of one image row in double precision. luma() and ssim() share it, so
// the public luma and the one SSIM works on differ only by float rounding.
void luma_row(const Image& image, int row, double* out) {
  const auto stride = static_cast<std::size_t>(image.channels);
  const std::size_t first_pixel = static_cast<std::size_t>(row) * static_cast<std::size_t>(image.width);
  const float* pixel = image.pixels.data() + first_pixel * stride;
  for (int x = 0; x < image.width; ++x, pixel += stride) {
    out[x] = image.channels == 1 ? static_cast<double>(pixel[0])
                                 : kLumaRed * pixel[0] + kLumaGreen * pixel[1] + kLumaBlue * pixel[2];
  }
}

using GaussianTaps = std::array<double, kWindowSize>;

// One-dimensional Gaussian taps normalised to sum 1. The reference window,
// fspecial('gaussian', 11, 1.5), is exp(-(x^2 + y^2) / (2 sigma^2)) normalised
// over the 11x11 square, which equals the outer product of these taps.
GaussianTaps gaussian_taps() {
  GaussianTaps taps{};
  constexpr int radius = kWindowSize / 2;
  double sum = 0.0;
  for (int i = 0; i < kWindowSize; ++i) {
    const double offset = i - radius;
    taps[static_cast<std::size_t>(i)] = std::exp(-(offset * offset) / (2.0 * kWindowSigma * kWindowSigma));
    sum += taps[static_cast<std::size_t>(i)];
  }
  for (double& tap : taps) tap /= sum;
  return taps;
}

// Gaussian-weighted first and second moments of the two lumas along one row,
// one value per 'valid' window position.
struct RowMoments {
  std::vector<double> x, y, xx, yy, xy;

  explicit RowMoments(std::size_t width) : x(width), y(width), xx(width), yy(width), xy(width) {}

  void clear() {
    for (auto* moment : {&x, &y, &xx, &yy, &xy}) std::fill(moment->begin(), moment->end(), 0.0);
  }
};

// Horizontal half of the separable window over one pair of luma rows.
// Tap-outer loops keep successive outputs independent so they vectorise.
void filter_row_horizontally(const std::vector<double>& luma_x, const std::vector<double>& luma_y,
                             const GaussianTaps& taps, RowMoments& out) {
  out.clear();
  const std::size_t width = out.x.size();
  for (std::size_t k = 0; k < taps.size(); ++k) {
    const double tap = taps[k];
    const double* px = luma_x.data() + k;
    const double* py = luma_y.data() + k;
    for (std::size_t i = 0; i < width; ++i) {
      out.x[i] += tap * px[i];
      out.y[i] += tap * py[i];
      out.xx[i] += tap * (px[i] * px[i]);
      out.yy[i] += tap * (py[i] * py[i]);
      out.xy[i] += tap * (px[i] * py[i]);
    }
  }
}

// Vertical half: combines the 11 horizontally filtered rows of one window
// position (oldest first) into the full 2-D windowed moments.
void filter_rows_vertically(const std::vector<RowMoments>& rows, std::size_t oldest, const GaussianTaps& taps,
                            RowMoments& out) {
  out.clear();
  const std::size_t width = out.x.size();
  for (std::size_t k = 0; k < taps.size(); ++k) {
    const double tap = taps[k];
    const RowMoments& row = rows[(oldest + k) % rows.size()];
    for (std::size_t i = 0; i < width; ++i) {
      out.x[i] += tap * row.x[i];
      out.y[i] += tap * row.y[i];
      out.xx[i] += tap * row.xx[i];
      out.yy[i] += tap * row.yy[i];
      out.xy[i] += tap * row.xy[i];
    }
  }
}

// Local SSIM from the windowed moments, eq. 13 of Wang et al. with the
// biased (weighted) variances of ssim_index.m: sigma^2 = E[x^2] - E[x]^2.
double local_ssim(double mean_x, double mean_y, double mean_xx, double mean_yy, double mean_xy) {
  const double variance_x = mean_xx - mean_x * mean_x;
  const double variance_y = mean_yy - mean_y * mean_y;
  const double covariance = mean_xy - mean_x * mean_y;
  const double numerator = (2.0 * mean_x * mean_y + kC1) * (2.0 * covariance + kC2);
  const double denominator = (mean_x * mean_x + mean_y * mean_y + kC1) * (variance_x + variance_y + kC2);
  return numerator / denominator;
}

}  // namespace

Image luma(const Image& image) {
  require_valid_layout(image);
  if (image.channels == 1) return image;
  Image grey(image.width, image.height, 1);
  std::vector<double> row(static_cast<std::size_t>(image.width));
  for (int y = 0; y < image.height; ++y) {
    luma_row(image, y, row.data());
    for (int x = 0; x < image.width; ++x) {
      grey.at(x, y, 0) = static_cast<float>(row[static_cast<std::size_t>(x)]);
    }
  }
  return grey;
}

PsnrResult psnr(const Image& a, const Image& b) {
  require_valid_layout(a);
  require_valid_layout(b);
  require_same_size(a, b);
  const int colours = colour_channel_count(a);
  if (colours != colour_channel_count(b)) {
    throw std::invalid_argument("images differ in colour channels: " + std::to_string(colours) + " vs " +
                                std::to_string(colour_channel_count(b)));
  }
  if (a.pixel_count() == 0) throw std::invalid_argument("PSNR of an empty image is undefined");

  const auto stride_a = static_cast<std::size_t>(a.channels);
  const auto stride_b = static_cast<std::size_t>(b.channels);
  double sum_squared_error = 0.0;
  for (std::size_t i = 0; i < a.pixel_count(); ++i) {
    const float* pixel_a = a.pixels.data() + i * stride_a;
    const float* pixel_b = b.pixels.data() + i * stride_b;
    for (int c = 0; c < colours; ++c) {
      const double difference = static_cast<double>(pixel_a[c]) - static_cast<double>(pixel_b[c]);
      sum_squared_error += difference * difference;
    }
  }

  PsnrResult result;
  result.mse = sum_squared_error / (static_cast<double>(a.pixel_count()) * colours);
  result.identical = result.mse == 0.0;
  result.psnr_db = result.identical ? std::numeric_limits<double>::infinity()
                                    : 10.0 * std::log10(kPsnrPeak * kPsnrPeak / result.mse);
  return result;
}

SsimResult ssim(const Image& a, const Image& b) {
  require_valid_layout(a);
  require_valid_layout(b);
  require_same_size(a, b);
  if (a.width < kWindowSize || a.height < kWindowSize) {
    throw std::invalid_argument("SSIM needs images of at least 11x11 pixels (its Gaussian window), got " +
                                size_text(a));
  }

  // Streams over the rows: a ring of the last 11 horizontally filtered rows
  // is all the state needed, so memory stays O(width) besides the map.
  const GaussianTaps taps = gaussian_taps();
  const int map_width = a.width - (kWindowSize - 1);
  const auto row_length = static_cast<std::size_t>(map_width);
  const int map_height = a.height - (kWindowSize - 1);
  std::vector<double> luma_a(static_cast<std::size_t>(a.width));
  std::vector<double> luma_b(static_cast<std::size_t>(a.width));
  std::vector<RowMoments> recent_rows(kWindowSize, RowMoments(row_length));
  RowMoments window(row_length);

  SsimResult result;
  result.map = Image(map_width, map_height, 1);
  double sum = 0.0;  // averaged in double, not from the float map
  for (int row = 0; row < a.height; ++row) {
    luma_row(a, row, luma_a.data());
    luma_row(b, row, luma_b.data());
    const auto slot = static_cast<std::size_t>(row % kWindowSize);
    filter_row_horizontally(luma_a, luma_b, taps, recent_rows[slot]);

    const int map_row = row - (kWindowSize - 1);  // window whose bottom row this is
    if (map_row < 0) continue;
    filter_rows_vertically(recent_rows, static_cast<std::size_t>(map_row % kWindowSize), taps, window);
    for (int x = 0; x < map_width; ++x) {
      const auto i = static_cast<std::size_t>(x);
      const double value = local_ssim(window.x[i], window.y[i], window.xx[i], window.yy[i], window.xy[i]);
      result.map.at(x, map_row, 0) = static_cast<float>(value);
      sum += value;
    }
  }
  result.mean_ssim = sum / (static_cast<double>(map_width) * static_cast<double>(map_height));
  return result;
}

}  // namespace fovlab::metrics
