#include "renderer/upsampling/upsample_filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace fovlab {

namespace {

double sinc(double t) {
  if (t == 0.0) return 1.0;
  const double x = std::numbers::pi * t;
  return std::sin(x) / x;
}

int kernel_radius(UpsampleFilter filter) { return filter == UpsampleFilter::lanczos3 ? 3 : 1; }

}  // namespace

const char* upsample_filter_name(UpsampleFilter filter) {
  switch (filter) {
    case UpsampleFilter::lanczos3:
      return "lanczos3";
    case UpsampleFilter::bilinear:
      return "bilinear";
    case UpsampleFilter::nearest:
      return "nearest";
  }
  return "lanczos3";
}

std::optional<UpsampleFilter> parse_upsample_filter(const std::string& name) {
  for (UpsampleFilter filter : {UpsampleFilter::lanczos3, UpsampleFilter::bilinear, UpsampleFilter::nearest})
    if (name == upsample_filter_name(filter)) return filter;
  return std::nullopt;
}

double upsample_kernel(UpsampleFilter filter, double t) {
  switch (filter) {
    case UpsampleFilter::lanczos3:
      return std::fabs(t) < 3.0 ? sinc(t) * sinc(t / 3.0) : 0.0;
    case UpsampleFilter::bilinear:
      return std::max(0.0, 1.0 - std::fabs(t));
    case UpsampleFilter::nearest:
      return (t >= -0.5 && t < 0.5) ? 1.0 : 0.0;
  }
  return 0.0;
}

std::vector<float> upsample_cell_weights(UpsampleFilter filter, int factor) {
  if (factor < 1 || factor > 8) throw std::invalid_argument("upsample_cell_weights: factor must be 1 to 8");
  const int radius = kernel_radius(filter);
  std::vector<float> weights(size_t(factor) * kUpsampleCellTaps, 0.0f);
  for (int phase = 0; phase < factor; ++phase) {
    // u relative to the cell's input pixel c is the same for every cell: floor(u) is c - 1 or c.
    const double u = (phase + 0.5) / factor - 0.5;
    const double floor_u = std::floor(u);
    const double fraction = u - floor_u;
    double sum = 0.0;
    for (int k = 1 - radius; k <= radius; ++k) sum += upsample_kernel(filter, fraction - k);
    for (int k = 1 - radius; k <= radius; ++k) {
      const int slot = int(floor_u) + k + 3;  // input pixel c + floor(u) + k
      weights[size_t(phase) * kUpsampleCellTaps + size_t(slot)] =
          static_cast<float>(upsample_kernel(filter, fraction - k) / sum);
    }
  }
  return weights;
}

Image upsample_reference(const Image& image, int factor, UpsampleFilter filter) {
  if (factor < 1 || factor > 8) throw std::invalid_argument("upsample_reference: factor must be 1 to 8");
  const int channels = image.channels;
  const int width_out = image.width * factor;
  const int height_out = image.height * factor;
  const int radius = kernel_radius(filter);
  // The taps and normalised weights of one output coordinate along an axis of `length` pixels.
  struct Taps {
    int first = 0;
    std::vector<double> weights;
  };
  const auto taps_for = [&](int out) {
    const double u = (out + 0.5) / factor - 0.5;
    Taps taps;
    taps.first = int(std::floor(u)) - radius + 1;
    double sum = 0.0;
    for (int k = taps.first; k <= int(std::floor(u)) + radius; ++k) {
      const double w = upsample_kernel(filter, u - k);
      taps.weights.push_back(w);
      sum += w;
    }
    for (double& w : taps.weights) w /= sum;
    return taps;
  };
  const auto clamp_index = [](int k, int length) { return std::clamp(k, 0, length - 1); };

  // Horizontal pass into doubles, then vertical.
  std::vector<double> rows(size_t(width_out) * size_t(image.height) * size_t(channels));
  for (int x = 0; x < width_out; ++x) {
    const Taps taps = taps_for(x);
    for (int y = 0; y < image.height; ++y) {
      for (int c = 0; c < channels; ++c) {
        double value = 0.0;
        for (size_t i = 0; i < taps.weights.size(); ++i)
          value += taps.weights[i] * image.at(clamp_index(taps.first + int(i), image.width), y, c);
        rows[(size_t(y) * size_t(width_out) + size_t(x)) * size_t(channels) + size_t(c)] = value;
      }
    }
  }
  Image out(width_out, height_out, channels);
  for (int y = 0; y < height_out; ++y) {
    const Taps taps = taps_for(y);
    for (int x = 0; x < width_out; ++x) {
      for (int c = 0; c < channels; ++c) {
        double value = 0.0;
        for (size_t i = 0; i < taps.weights.size(); ++i) {
          const int row = clamp_index(taps.first + int(i), image.height);
          value += taps.weights[i] * rows[(size_t(row) * size_t(width_out) + size_t(x)) * size_t(channels) + size_t(c)];
        }
        out.at(x, y, c) = static_cast<float>(value);
      }
    }
  }
  return out;
}

}  // namespace fovlab
