#include "analysis/fitting/psychometric_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>

#include "analysis/fitting/binomial_sampler.h"
#include "analysis/fitting/nelder_mead.h"
#include "study/psychometric/psychometric_detail.h"
#include "core/number_text.h"
#include "core/prng.h"

namespace fovlab::analysis {

namespace {

using detail::Point;

// Probabilities are kept in [kClamp, 1 - kClamp] inside the log likelihood only (the model itself
// is never clamped), so a fit that puts p_report = 0 where k > 0 costs a large but finite penalty.
constexpr double kClamp = 1e-12;

// The search box, in the scaled coordinates below (for the Weibull the level axis, and so the
// range, is log(level)). The threshold may lie up to kThresholdReach level ranges beyond either
// end of the tested range; slope * range lies in [kMinScaledSlope, kMaxScaledSlope] (from an
// essentially flat function to one that steps between levels 10^-4 ranges apart); u (lapse =
// max_lapse * logistic(u)) in [-kLapseReach, kLapseReach], i.e. the lapse comes within
// max_lapse * 4e-18 of its bounds. The box only makes fits of degenerate data (all at floor, no
// trend, ...) finite: such fits end on its faces and get a note.
constexpr double kThresholdReach = 10.0;
constexpr double kMinScaledSlope = 1e-3;
constexpr double kMaxScaledSlope = 1e4;
constexpr double kLapseReach = 40.0;

constexpr int kIterationBudget = 4000;  // per Nelder-Mead run
constexpr int kMaxRestarts = 4;         // fresh simplices around the best point, until no gain

double logistic(double u) { return u >= 0.0 ? 1.0 / (1.0 + std::exp(-u)) : std::exp(u) / (1.0 + std::exp(u)); }

double log_binomial_coefficient(double n, double k) {
  return std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0);
}

// The data sorted by level (so any order of the input gives bit-identical results), with the
// level axis the fit works on: the level itself, or its log for the Weibull, whose p_see is a
// function of log(level) - log(threshold).
struct Problem {
  PsychometricShape shape = PsychometricShape::logistic;
  bool rising = true;
  double guess = 0.0;
  double max_lapse = 0.0;
  int dimensions = 3;  // 2 when max_lapse == 0 (the lapse is then fixed at 0)
  std::vector<double> levels;
  std::vector<double> n;
  std::vector<double> k;
  double centre = 0.0;  // of the level axis
  double range = 1.0;   // max - min on the level axis, > 0

  // Scaled coordinates z: z0 = (threshold on the axis - centre) / range, z1 = log(slope * range),
  // z2 = u with lapse = max_lapse * logistic(u).
  PsychometricModel model(const Point& z) const {
    PsychometricModel m;
    m.shape = shape;
    m.rising = rising;
    m.guess = guess;
    const double axis_threshold = centre + range * z[0];
    m.parameters.threshold = shape == PsychometricShape::weibull ? std::exp(axis_threshold) : axis_threshold;
    m.parameters.slope = std::exp(z[1]) / range;
    m.parameters.lapse = dimensions == 3 ? max_lapse * logistic(z[2]) : 0.0;
    return m;
  }
  // log L without the binomial coefficients.
  double log_likelihood_kernel(const PsychometricModel& m, const std::vector<double>& counts) const {
    double sum = 0.0;
    for (size_t i = 0; i < levels.size(); ++i) {
      const fovlab::detail::ReportProbabilities p = fovlab::detail::report_probabilities(m, levels[i]);
      const double report = std::clamp(p.report, kClamp, 1.0 - kClamp);
      const double not_report = std::clamp(p.not_report, kClamp, 1.0 - kClamp);
      if (counts[i] > 0.0) sum += counts[i] * std::log(report);
      if (n[i] - counts[i] > 0.0) sum += (n[i] - counts[i]) * std::log(not_report);
    }
    return sum;
  }
  double saturated_kernel(const std::vector<double>& counts) const {
    double sum = 0.0;  // 0 log 0 = 0
    for (size_t i = 0; i < levels.size(); ++i) {
      const double kk = counts[i];
      const double rest = n[i] - kk;
      if (kk > 0.0) sum += kk * std::log(kk / n[i]);
      if (rest > 0.0) sum += rest * std::log(rest / n[i]);
    }
    return sum;
  }

  detail::NelderMeadSettings settings() const {
    detail::NelderMeadSettings s;
    s.dimensions = dimensions;
    s.lower = {-0.5 - kThresholdReach, std::log(kMinScaledSlope), -kLapseReach};
    s.upper = {0.5 + kThresholdReach, std::log(kMaxScaledSlope), kLapseReach};
    s.initial_step = {0.1, 0.5, 1.0};
    s.max_iterations = kIterationBudget;
    s.f_tolerance = 1e-13;
    s.x_tolerance = 1e-8;
    // Size measured on (threshold / range, log slope, lapse / max_lapse): u itself may wander far
    // into a flat tail where the lapse no longer changes.
    const int dims = dimensions;
    s.spread = [dims](const Point& a, const Point& b) {
      double m = std::max(std::fabs(a[0] - b[0]), std::fabs(a[1] - b[1]));
      if (dims == 3) m = std::max(m, std::fabs(logistic(a[2]) - logistic(b[2])));
      return m;
    };
    return s;
  }
};

struct Optimum {
  Point z{};
  double kernel = -std::numeric_limits<double>::infinity();  // log L without coefficients
  bool converged = false;
};

// Nelder-Mead from `start`, then restarted from a fresh simplex around the best point while that
// still gains (a simplex can collapse early on a ridge); converged if the last run converged.
template <typename Objective>
detail::NelderMeadResult minimise_with_restarts(const Objective& objective, const Point& start,
                                                const detail::NelderMeadSettings& s) {
  detail::NelderMeadResult best = detail::nelder_mead(objective, start, s);
  for (int restart = 0; restart < kMaxRestarts; ++restart) {
    const detail::NelderMeadResult again = detail::nelder_mead(objective, best.x, s);
    const bool gained = again.f < best.f - s.f_tolerance * (1.0 + std::fabs(best.f));
    if (again.f <= best.f) best = again;
    else best.converged = again.converged && best.converged;
    if (!gained) break;
  }
  return best;
}

Optimum minimise_from(const Problem& problem, const std::vector<double>& counts, const Point& start) {
  const auto objective = [&](const Point& z) { return -problem.log_likelihood_kernel(problem.model(z), counts); };
  const detail::NelderMeadResult best = minimise_with_restarts(objective, start, problem.settings());
  return {best.x, -best.f, best.converged};
}

bool better_optimum(const Optimum& candidate, const Optimum& incumbent) {
  if (candidate.converged != incumbent.converged) return candidate.converged;
  return candidate.kernel > incumbent.kernel;  // strictly: ties keep the earlier start
}

// The best optimum over the starts (deterministic: a strictly better one replaces the incumbent).
Optimum best_of(const Problem& problem, const std::vector<double>& counts, const std::vector<Point>& starts) {
  Optimum best;
  bool have = false;
  for (const Point& start : starts) {
    const Optimum o = minimise_from(problem, counts, start);
    if (!have || better_optimum(o, best)) {
      best = o;
      have = true;
    }
  }
  return best;
}

// Lapse starts, as u (lapse = max_lapse * logistic(u)): 0.047 and 0.73 of max_lapse. The lapse
// likelihood can have a second local optimum at the other bound, and near either bound it is
// flat in u, so a simplex started there never sees the other side: both are tried.
constexpr double kLapseStarts[] = {-3.0, 1.0};

// ML starts: thresholds at 5 points across the tested range x slope * range in {1.5, 6, 24}
// (shallower than, about as steep as, and steeper than the range) x the two lapse starts.
// (Without a free lapse, only the first lapse start: the coordinate is unused.)
std::vector<Point> grid_starts(int dimensions) {
  std::vector<Point> starts;
  for (double t : {-0.4, -0.2, 0.0, 0.2, 0.4})
    for (double scaled_slope : {1.5, 6.0, 24.0})
      for (double u : kLapseStarts) {
        starts.push_back({t, std::log(scaled_slope), u});
        if (dimensions < 3) break;
      }
  return starts;
}

// Bootstrap starts: the ML fit itself (its u pulled into [-3, 3], off the flat tail), and its
// threshold and slope with each of the lapse starts.
std::vector<Point> starts_near(const Point& ml, int dimensions) {
  std::vector<Point> starts;
  Point first = ml;
  first[2] = std::clamp(ml[2], -3.0, 3.0);
  starts.push_back(first);
  if (dimensions == 3)
    for (double u : kLapseStarts) starts.push_back({ml[0], ml[1], u});
  return starts;
}

// Percentile (type 7: linear interpolation between order statistics, as numpy's default) of
// sorted values.
double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return std::nan("");
  const double h = (static_cast<double>(sorted.size()) - 1.0) * q;
  const auto below = static_cast<size_t>(std::floor(h));
  const size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (h - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

ParameterInterval interval(std::vector<double> values, double confidence) {
  std::sort(values.begin(), values.end());
  return {percentile(values, (1.0 - confidence) / 2.0), percentile(values, (1.0 + confidence) / 2.0)};
}

// ---- Profile likelihood --------------------------------------------------------------------------
// The profile log likelihood of coordinate `fixed` at `value`: the best kernel over the other
// coordinates, from the given starts (their `fixed` coordinate is overwritten).
Optimum profile_at(const Problem& problem, const std::vector<double>& counts, int fixed, double value,
                   const std::vector<Point>& starts) {
  const detail::NelderMeadSettings full = problem.settings();
  detail::NelderMeadSettings reduced = full;
  reduced.dimensions = problem.dimensions - 1;
  int free_axes[detail::kMaxDimensions] = {};
  for (int j = 0, r = 0; j < problem.dimensions; ++j)
    if (j != fixed) free_axes[r++] = j;
  const auto expand = [&](const Point& sub) {
    Point z{};
    z[fixed] = value;
    for (int r = 0; r < reduced.dimensions; ++r) z[free_axes[r]] = sub[r];
    return z;
  };
  for (int r = 0; r < reduced.dimensions; ++r) {
    reduced.lower[r] = full.lower[free_axes[r]];
    reduced.upper[r] = full.upper[free_axes[r]];
    reduced.initial_step[r] = full.initial_step[free_axes[r]];
  }
  reduced.spread = [&](const Point& a, const Point& b) { return full.spread(expand(a), expand(b)); };
  const auto objective = [&](const Point& sub) {
    return -problem.log_likelihood_kernel(problem.model(expand(sub)), counts);
  };
  Optimum best;
  bool have = false;
  for (const Point& start : starts) {
    Point sub{};
    for (int r = 0; r < reduced.dimensions; ++r) sub[r] = start[free_axes[r]];
    const detail::NelderMeadResult o = minimise_with_restarts(objective, sub, reduced);
    const Optimum candidate{expand(o.x), -o.f, o.converged};
    // The profile is a maximum: the highest likelihood found wins, converged or not (preferring a
    // converged lower one would end the interval too early).
    if (!have || candidate.kernel > best.kernel) {
      best = candidate;
      have = true;
    }
  }
  return best;
}

// One end of the profile-likelihood interval of coordinate `axis` (direction -1: below the
// estimate, +1: above): the value where the profile kernel falls to `target`, found by stepping
// outwards (doubling steps from `first_step`) until the profile is below it, then by bisection.
// nullopt when the profile stays above the target up to the search box's face: the data do not
// bound the parameter on that side.
std::optional<double> profile_end(const Problem& problem, const std::vector<double>& counts, const Optimum& ml,
                                  int axis, int direction, double target, double first_step) {
  const detail::NelderMeadSettings s = problem.settings();
  const double face = direction < 0 ? s.lower[axis] : s.upper[axis];
  std::vector<Point> starts = starts_near(ml.z, problem.dimensions);
  double inside = ml.z[axis];
  double step = first_step;
  std::optional<double> outside;
  while (!outside) {
    const double candidate = direction < 0 ? std::max(face, inside - step) : std::min(face, inside + step);
    const Optimum o = profile_at(problem, counts, axis, candidate, starts);
    if (o.kernel < target) {
      outside = candidate;
    } else {
      if (candidate == face) return std::nullopt;
      inside = candidate;
      starts.front() = o.z;  // warm start: the profile's optimum moves smoothly with the value
      step *= 2.0;
    }
  }
  for (int i = 0; i < 40 && std::fabs(*outside - inside) > 1e-9; ++i) {
    const double middle = 0.5 * (inside + *outside);
    const Optimum o = profile_at(problem, counts, axis, middle, starts);
    if (o.kernel < target) {
      outside = middle;
    } else {
      inside = middle;
      starts.front() = o.z;
    }
  }
  return 0.5 * (inside + *outside);
}

void validate(const std::vector<LevelCounts>& data, const FitOptions& options) {
  if (data.empty()) throw std::invalid_argument("fit_psychometric: no data");
  if (options.shape != PsychometricShape::logistic && options.shape != PsychometricShape::weibull &&
      options.shape != PsychometricShape::cumulative_normal)
    throw std::invalid_argument("fit_psychometric: unknown shape");
  if (!(options.guess >= 0.0 && options.guess < 1.0))
    throw std::invalid_argument("fit_psychometric: guess must lie in [0, 1)");
  if (!(options.max_lapse >= 0.0 && options.max_lapse < 1.0 - options.guess))
    throw std::invalid_argument("fit_psychometric: max_lapse must lie in [0, 1 - guess)");
  if (options.bootstrap_samples < 0) throw std::invalid_argument("fit_psychometric: bootstrap_samples must be >= 0");
  if (!(options.confidence > 0.0 && options.confidence < 1.0))
    throw std::invalid_argument("fit_psychometric: confidence must lie in (0, 1)");
  for (const LevelCounts& d : data) {
    if (!std::isfinite(d.level)) throw std::invalid_argument("fit_psychometric: a level is not finite");
    if (d.n == 0) throw std::invalid_argument("fit_psychometric: a level has n = 0 trials");
    if (d.k > d.n) throw std::invalid_argument("fit_psychometric: a level has k > n");
    if (options.shape == PsychometricShape::weibull && !(d.level > 0.0))
      throw std::invalid_argument("fit_psychometric: a Weibull needs every level > 0");
  }
  const auto [lowest, highest] = std::minmax_element(
      data.begin(), data.end(), [](const LevelCounts& a, const LevelCounts& b) { return a.level < b.level; });
  if (!(highest->level > lowest->level))
    throw std::invalid_argument("fit_psychometric: needs at least two distinct levels");
}

Problem make_problem(const std::vector<LevelCounts>& data, const FitOptions& options) {
  std::vector<LevelCounts> sorted = data;
  std::stable_sort(sorted.begin(), sorted.end(), [](const LevelCounts& a, const LevelCounts& b) {
    return a.level < b.level || (a.level == b.level && (a.n < b.n || (a.n == b.n && a.k < b.k)));
  });
  Problem p;
  p.shape = options.shape;
  p.rising = options.rising;
  p.guess = options.guess;
  p.max_lapse = options.max_lapse;
  p.dimensions = options.max_lapse > 0.0 ? 3 : 2;
  for (const LevelCounts& d : sorted) {
    p.levels.push_back(d.level);
    p.n.push_back(static_cast<double>(d.n));
    p.k.push_back(static_cast<double>(d.k));
  }
  const auto axis = [&](double level) { return p.shape == PsychometricShape::weibull ? std::log(level) : level; };
  const double lo = axis(p.levels.front());
  const double hi = axis(p.levels.back());
  p.centre = 0.5 * (lo + hi);
  p.range = hi - lo;
  if (!(p.range > 0.0) || !std::isfinite(p.range))
    throw std::invalid_argument("fit_psychometric: the levels span no usable range");
  return p;
}

// The three profile-likelihood intervals of the ML fit `ml` (z coordinates), in natural units.
void add_profile_intervals(const Problem& problem, const Optimum& ml, double confidence, PsychometricFit& fit) {
  const double inf = std::numeric_limits<double>::infinity();
  const double target = ml.kernel - 0.5 * boost::math::quantile(boost::math::chi_squared(1.0), confidence);
  const auto end = [&](int axis, int direction, double first_step) {
    return profile_end(problem, problem.k, ml, axis, direction, target, first_step);
  };
  const bool weibull = problem.shape == PsychometricShape::weibull;
  const auto threshold_at = [&](double z0) {
    const double axis = problem.centre + problem.range * z0;
    return weibull ? std::exp(axis) : axis;
  };
  const std::string percent = format_number(100.0 * confidence, 6) + " %";
  const auto unbounded = [&](const char* parameter, const char* side) {
    append_note(fit.note, "the " + percent + " profile-likelihood interval of the " + parameter + " is unbounded " +
                              side + " (the data do not limit it)");
  };
  const std::optional<double> t_low = end(0, -1, 0.02), t_high = end(0, +1, 0.02);
  fit.threshold_interval = {t_low ? threshold_at(*t_low) : (weibull ? 0.0 : -inf),
                            t_high ? threshold_at(*t_high) : inf};
  if (!t_low) unbounded("threshold", "below");
  if (!t_high) unbounded("threshold", "above");
  const std::optional<double> s_low = end(1, -1, 0.1), s_high = end(1, +1, 0.1);
  fit.slope_interval = {s_low ? std::exp(*s_low) / problem.range : 0.0,
                        s_high ? std::exp(*s_high) / problem.range : inf};
  if (!s_high) unbounded("slope", "above");
  if (problem.dimensions == 3) {
    const std::optional<double> l_low = end(2, -1, 0.5), l_high = end(2, +1, 0.5);
    fit.lapse_interval = {l_low ? problem.max_lapse * logistic(*l_low) : 0.0,
                          l_high ? problem.max_lapse * logistic(*l_high) : problem.max_lapse};
  } else {
    fit.lapse_interval = {0.0, 0.0};
  }
}

}  // namespace

PsychometricFit fit_psychometric(const std::vector<LevelCounts>& data, const FitOptions& options) {
  validate(data, options);
  const Problem problem = make_problem(data, options);
  const size_t levels = problem.levels.size();

  double log_coefficients = 0.0;
  for (size_t i = 0; i < levels; ++i) log_coefficients += log_binomial_coefficient(problem.n[i], problem.k[i]);

  const Optimum best = best_of(problem, problem.k, grid_starts(problem.dimensions));
  PsychometricFit fit;
  fit.model = problem.model(best.z);
  fit.converged = best.converged;
  fit.log_likelihood = best.kernel + log_coefficients;
  fit.deviance = std::max(0.0, 2.0 * (problem.saturated_kernel(problem.k) - best.kernel));
  fit.degrees_of_freedom = static_cast<int>(levels) - 3;

  // Notes on fits the data cannot pin down.
  bool all_floor = true;
  bool all_ceiling = true;
  size_t distinct = 1;
  for (size_t i = 0; i < levels; ++i) {
    all_floor = all_floor && problem.k[i] == 0.0;
    all_ceiling = all_ceiling && problem.k[i] == problem.n[i];
    if (i > 0 && problem.levels[i] != problem.levels[i - 1]) ++distinct;
  }
  if (all_floor) append_note(fit.note, "every level at floor (k = 0): the threshold is beyond the tested range");
  if (all_ceiling) append_note(fit.note, "every level at ceiling (k = n): the threshold is beyond the tested range");
  if (distinct == 2) append_note(fit.note, "only two levels: threshold, slope and lapse are not all identifiable");
  const detail::NelderMeadSettings s = problem.settings();
  const double edge = 1e-6;
  if (best.z[0] <= s.lower[0] + edge || best.z[0] >= s.upper[0] - edge)
    append_note(fit.note, "threshold at its search bound (10 level ranges beyond the tested range)");
  if (best.z[1] <= s.lower[1] + edge)
    append_note(fit.note, "slope at its lower search bound: the data show no trend with the level");
  if (best.z[1] >= s.upper[1] - edge)
    append_note(fit.note, "slope at its upper search bound: the data jump between adjacent levels");
  const double lowest_level = problem.levels.front();
  const double highest_level = problem.levels.back();
  if (!all_floor && !all_ceiling &&
      (fit.model.parameters.threshold < lowest_level || fit.model.parameters.threshold > highest_level))
    append_note(fit.note, "threshold outside the tested levels: an extrapolation");
  if (!best.converged) append_note(fit.note, "the optimiser did not converge within its iteration budget");

  add_profile_intervals(problem, best, options.confidence, fit);

  // Parametric bootstrap.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  fit.bootstrap_threshold_interval = fit.bootstrap_slope_interval = fit.bootstrap_lapse_interval = {nan, nan};
  fit.deviance_p_value = nan;
  if (options.bootstrap_samples > 0) {
    std::vector<double> p_report(levels);
    for (size_t i = 0; i < levels; ++i) p_report[i] = fit.model.p_report(problem.levels[i]);
    const std::vector<Point> starts = starts_near(best.z, problem.dimensions);
    std::vector<double> thresholds, slopes, lapses, deviances;
    std::vector<double> counts(levels);
    for (int b = 0; b < options.bootstrap_samples; ++b) {
      Pcg32 rng(derive_seed(options.seed, static_cast<uint64_t>(b)));
      for (size_t i = 0; i < levels; ++i)
        counts[i] = static_cast<double>(draw_binomial(static_cast<uint64_t>(problem.n[i]), p_report[i], rng));
      const Optimum o = best_of(problem, counts, starts);
      if (!o.converged) {
        ++fit.bootstrap_failures;
        continue;
      }
      const PsychometricModel m = problem.model(o.z);
      thresholds.push_back(m.parameters.threshold);
      slopes.push_back(m.parameters.slope);
      lapses.push_back(m.parameters.lapse);
      deviances.push_back(std::max(0.0, 2.0 * (problem.saturated_kernel(counts) - o.kernel)));
    }
    fit.bootstrap_samples = static_cast<int>(thresholds.size());
    if (!thresholds.empty()) {
      fit.bootstrap_threshold_interval = interval(thresholds, options.confidence);
      fit.bootstrap_slope_interval = interval(slopes, options.confidence);
      fit.bootstrap_lapse_interval = interval(lapses, options.confidence);
      const auto at_least =
          std::count_if(deviances.begin(), deviances.end(), [&](double d) { return d >= fit.deviance; });
      fit.deviance_p_value = static_cast<double>(at_least) / static_cast<double>(deviances.size());
    }
    if (fit.bootstrap_failures > 0)
      append_note(fit.note, std::to_string(fit.bootstrap_failures) + " bootstrap fits did not converge");
  }
  return fit;
}

void append_note(std::string& note, const std::string& text) {
  if (!note.empty()) note += "; ";
  note += text;
}

}  // namespace fovlab::analysis
