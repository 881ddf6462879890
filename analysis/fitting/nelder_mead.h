#pragma once
// A small Nelder-Mead simplex minimiser for the psychometric fits (at most a few parameters).
// Debian 12 packages no C++ optimisation library that fits here (Boost.Math has only
// one-dimensional minimisers), so this is our own: the standard method with the coefficients
// of Lagarias et al. (1998) (reflection 1, expansion 2, contraction 1/2, shrink 1/2), deterministic
// (ties keep the earlier vertex), with a box: points outside it count as +infinity, which the
// method treats as "worse than everything" and contracts away from.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

namespace fovlab::analysis::detail {

constexpr int kMaxDimensions = 3;
using Point = std::array<double, kMaxDimensions>;

struct NelderMeadSettings {
  int dimensions = 3;
  Point lower{};  // box (inclusive)
  Point upper{};
  Point initial_step{};  // edge lengths of the starting simplex
  int max_iterations = 4000;
  // Converged when, over every vertex, the objective is within f_tolerance * (1 + |f_best|) of the
  // best and `spread(vertex, best)` <= x_tolerance: the simplex has shrunk onto a point.
  double f_tolerance = 1e-12;
  double x_tolerance = 1e-8;
  // Distance used for the size test; by default the largest coordinate difference.
  std::function<double(const Point&, const Point&)> spread;
};

struct NelderMeadResult {
  Point x{};
  double f = std::numeric_limits<double>::infinity();
  int iterations = 0;
  bool converged = false;
};

template <typename Objective>
NelderMeadResult nelder_mead(const Objective& objective, const Point& start, const NelderMeadSettings& settings) {
  const int d = settings.dimensions;
  const auto inside = [&](const Point& p) {
    for (int j = 0; j < d; ++j)
      if (!(p[j] >= settings.lower[j] && p[j] <= settings.upper[j])) return false;
    return true;
  };
  const auto evaluate = [&](const Point& p) {
    if (!inside(p)) return std::numeric_limits<double>::infinity();
    const double f = objective(p);
    return std::isnan(f) ? std::numeric_limits<double>::infinity() : f;
  };
  const auto distance = [&](const Point& a, const Point& b) {
    if (settings.spread) return settings.spread(a, b);
    double m = 0.0;
    for (int j = 0; j < d; ++j) m = std::max(m, std::fabs(a[j] - b[j]));
    return m;
  };

  std::array<Point, kMaxDimensions + 1> x{};
  std::array<double, kMaxDimensions + 1> f{};
  Point origin = start;
  for (int j = 0; j < d; ++j) origin[j] = std::clamp(origin[j], settings.lower[j], settings.upper[j]);
  x[0] = origin;
  for (int i = 1; i <= d; ++i) {
    x[i] = origin;
    const int j = i - 1;
    const double step = settings.initial_step[j];
    // Step inwards when the start lies on (or near) the upper side of the box.
    x[i][j] = origin[j] + step <= settings.upper[j] ? origin[j] + step : origin[j] - step;
  }
  for (int i = 0; i <= d; ++i) f[i] = evaluate(x[i]);

  std::array<int, kMaxDimensions + 1> order{};
  NelderMeadResult result;
  for (int iteration = 0;; ++iteration) {
    // Sort the vertices best first (stable: ties keep their order, so runs replay exactly).
    for (int i = 0; i <= d; ++i) order[i] = i;
    std::stable_sort(order.begin(), order.begin() + d + 1, [&](int a, int b) { return f[a] < f[b]; });
    {
      std::array<Point, kMaxDimensions + 1> xs{};
      std::array<double, kMaxDimensions + 1> fs{};
      for (int i = 0; i <= d; ++i) {
        xs[i] = x[order[i]];
        fs[i] = f[order[i]];
      }
      x = xs;
      f = fs;
    }
    bool small = std::isfinite(f[0]);
    for (int i = 1; i <= d && small; ++i) {
      small =
          f[i] - f[0] <= settings.f_tolerance * (1.0 + std::fabs(f[0])) && distance(x[i], x[0]) <= settings.x_tolerance;
    }
    if (small || iteration >= settings.max_iterations) {
      result.x = x[0];
      result.f = f[0];
      result.iterations = iteration;
      result.converged = small;
      return result;
    }

    Point centroid{};
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) centroid[j] += x[i][j] / d;
    const auto along = [&](double t) {  // centroid + t * (centroid - worst)
      Point p{};
      for (int j = 0; j < d; ++j) p[j] = centroid[j] + t * (centroid[j] - x[d][j]);
      return p;
    };
    const Point reflected = along(1.0);
    const double f_reflected = evaluate(reflected);
    if (f_reflected < f[0]) {
      const Point expanded = along(2.0);
      const double f_expanded = evaluate(expanded);
      if (f_expanded < f_reflected) {
        x[d] = expanded;
        f[d] = f_expanded;
      } else {
        x[d] = reflected;
        f[d] = f_reflected;
      }
      continue;
    }
    if (f_reflected < f[d - 1]) {
      x[d] = reflected;
      f[d] = f_reflected;
      continue;
    }
    bool accepted = false;
    if (f_reflected < f[d]) {  // outside contraction
      const Point contracted = along(0.5);
      const double f_contracted = evaluate(contracted);
      if (f_contracted <= f_reflected) {
        x[d] = contracted;
        f[d] = f_contracted;
        accepted = true;
      }
    } else {  // inside contraction
      const Point contracted = along(-0.5);
      const double f_contracted = evaluate(contracted);
      if (f_contracted < f[d]) {
        x[d] = contracted;
        f[d] = f_contracted;
        accepted = true;
      }
    }
    if (!accepted) {  // shrink towards the best vertex
      for (int i = 1; i <= d; ++i) {
        for (int j = 0; j < d; ++j) x[i][j] = x[0][j] + 0.5 * (x[i][j] - x[0][j]);
        f[i] = evaluate(x[i]);
      }
    }
  }
}

}  // namespace fovlab::analysis::detail
