#include "analysis/statistics/mean_interval.h"

#include <cmath>

#include <boost/math/distributions/students_t.hpp>

namespace fovlab::analysis {

MeanInterval mean_with_t_interval(const std::vector<double>& values) {
  MeanInterval summary;
  summary.count = static_cast<int>(values.size());
  if (values.empty()) return summary;
  double sum = 0.0;
  for (double value : values) sum += value;
  const double mean = sum / double(values.size());
  summary.mean = mean;
  if (values.size() >= 2) {
    double squares = 0.0;
    for (double value : values) squares += (value - mean) * (value - mean);
    summary.sd = std::sqrt(squares / double(values.size() - 1));
    const double t = boost::math::quantile(boost::math::students_t(double(values.size() - 1)), 0.975);
    const double half_width = t * *summary.sd / std::sqrt(double(values.size()));
    summary.mean_lower = mean - half_width;
    summary.mean_upper = mean + half_width;
  }
  return summary;
}

}  // namespace fovlab::analysis
