// Tests of analysis/fitting: the psychometric functions, the binomial sampler of the
// bootstrap, maximum-likelihood fits (recovery, an independent SciPy reference, edge cases) and the
// parametric bootstrap (replay, coverage).
#include "analysis/fitting/binomial_sampler.h"
#include "analysis/fitting/psychometric_fit.h"
#include "study/psychometric/psychometric_function.h"

#include <gtest/gtest.h>

#include <boost/math/distributions/binomial.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/prng.h"

namespace fovlab::analysis {
namespace {

constexpr PsychometricShape kShapes[] = {PsychometricShape::logistic, PsychometricShape::weibull,
                                         PsychometricShape::cumulative_normal};

PsychometricModel make_model(PsychometricShape shape, bool rising, double guess, double threshold, double slope,
                             double lapse) {
  PsychometricModel m;
  m.shape = shape;
  m.rising = rising;
  m.guess = guess;
  m.parameters = {threshold, slope, lapse};
  return m;
}

// The binomial log likelihood with coefficients, written out again here (0 log 0 = 0, p clamped to
// [1e-12, 1 - 1e-12] as documented).
double log_likelihood(const std::vector<LevelCounts>& data, const PsychometricModel& m) {
  double sum = 0.0;
  for (const LevelCounts& d : data) {
    const double n = static_cast<double>(d.n), k = static_cast<double>(d.k);
    const double p = std::clamp(m.p_report(d.level), 1e-12, 1.0 - 1e-12);
    sum += std::lgamma(n + 1) - std::lgamma(k + 1) - std::lgamma(n - k + 1);
    if (k > 0) sum += k * std::log(p);
    if (n - k > 0) sum += (n - k) * std::log1p(-p);
  }
  return sum;
}

double saturated_log_likelihood(const std::vector<LevelCounts>& data) {
  double sum = 0.0;
  for (const LevelCounts& d : data) {
    const double n = static_cast<double>(d.n), k = static_cast<double>(d.k);
    sum += std::lgamma(n + 1) - std::lgamma(k + 1) - std::lgamma(n - k + 1);
    if (k > 0) sum += k * std::log(k / n);
    if (n - k > 0) sum += (n - k) * std::log((n - k) / n);
  }
  return sum;
}

std::vector<LevelCounts> expected_counts(const PsychometricModel& m, const std::vector<double>& levels, uint64_t n) {
  std::vector<LevelCounts> data;
  for (double level : levels)
    data.push_back({level, n, static_cast<uint64_t>(std::llround(static_cast<double>(n) * m.p_report(level)))});
  return data;
}

std::vector<LevelCounts> simulate(const PsychometricModel& m, const std::vector<double>& levels, uint64_t n,
                                  uint64_t seed) {
  Pcg32 rng(seed);
  std::vector<LevelCounts> data;
  for (double level : levels) data.push_back({level, n, draw_binomial(n, m.p_report(level), rng)});
  return data;
}

bool finite_model(const PsychometricModel& m) {
  return std::isfinite(m.parameters.threshold) && std::isfinite(m.parameters.slope) &&
         std::isfinite(m.parameters.lapse);
}

// --- psychometric functions ---------------------------------------------------------------------

TEST(PsychometricFunction, ShapeNames) {
  EXPECT_STREQ(shape_name(PsychometricShape::logistic), "logistic");
  EXPECT_STREQ(shape_name(PsychometricShape::weibull), "weibull");
  EXPECT_STREQ(shape_name(PsychometricShape::cumulative_normal), "cumulative_normal");
}

TEST(PsychometricFunction, HalfAtThresholdAndDirection) {
  for (PsychometricShape shape : kShapes) {
    for (bool rising : {true, false}) {
      const PsychometricModel m = make_model(shape, rising, 0.5, 2.0, 3.0, 0.04);
      SCOPED_TRACE(std::string(shape_name(shape)) + (rising ? " rising" : " falling"));
      EXPECT_NEAR(m.p_see(2.0), 0.5, 1e-15);
      EXPECT_NEAR(m.p_report(2.0), 0.5 + 0.46 * 0.5, 1e-15);
      EXPECT_EQ(m.p_see(2.5) > m.p_see(1.5), rising);
      EXPECT_NEAR(m.p_report(2.5), 0.5 + 0.46 * m.p_see(2.5), 1e-15);
    }
  }
}

TEST(PsychometricFunction, ClosedForms) {
  const double x = 0.7;
  EXPECT_NEAR(make_model(PsychometricShape::logistic, true, 0, 1.0, 2.0, 0).p_see(1.0 + x),
              1.0 / (1.0 + std::exp(-2.0 * x)), 1e-15);
  EXPECT_NEAR(make_model(PsychometricShape::logistic, false, 0, 1.0, 2.0, 0).p_see(1.0 + x),
              1.0 / (1.0 + std::exp(2.0 * x)), 1e-15);
  // Phi(1) and Phi(-2), from tables.
  EXPECT_NEAR(make_model(PsychometricShape::cumulative_normal, true, 0, 1.0, 2.0, 0).p_see(1.5), 0.8413447460685429,
              1e-15);
  EXPECT_NEAR(make_model(PsychometricShape::cumulative_normal, false, 0, 1.0, 2.0, 0).p_see(2.0), 0.0227501319481792,
              1e-15);
  EXPECT_NEAR(make_model(PsychometricShape::weibull, true, 0, 2.0, 3.0, 0).p_see(4.0),
              1.0 - std::exp(-std::log(2.0) * 8.0), 1e-15);
  EXPECT_NEAR(make_model(PsychometricShape::weibull, false, 0, 2.0, 3.0, 0).p_see(1.0), std::exp(-std::log(2.0) / 8.0),
              1e-15);
}

TEST(PsychometricFunction, StableInTheTails) {
  for (PsychometricShape shape : kShapes) {
    for (bool rising : {true, false}) {
      const PsychometricModel m = make_model(shape, rising, 0.0, 1.0, 1e6, 0.0);
      for (double level : {1e-300, 1e-9, 0.5, 1.0 + 1e-12, 2.0, 1e300}) {
        const double p = m.p_see(level);
        EXPECT_TRUE(p >= 0.0 && p <= 1.0) << shape_name(shape) << " " << level << " -> " << p;
      }
      EXPECT_EQ(m.p_see(1e300), rising ? 1.0 : 0.0);
      EXPECT_EQ(m.p_see(1e-300), rising ? 0.0 : 1.0);
    }
  }
  // Weibull below or at zero: the limit.
  EXPECT_EQ(make_model(PsychometricShape::weibull, true, 0.0, 1.0, 2.0, 0.0).p_see(0.0), 0.0);
  EXPECT_EQ(make_model(PsychometricShape::weibull, false, 0.0, 1.0, 2.0, 0.0).p_see(-3.0), 1.0);
  // A tiny p_see keeps its relative precision (no 1 - (1 - p) cancellation).
  EXPECT_NEAR(make_model(PsychometricShape::logistic, true, 0.0, 0.0, 1.0, 0.0).p_see(-50.0) / std::exp(-50.0), 1.0,
              1e-12);
  EXPECT_NEAR(make_model(PsychometricShape::weibull, true, 0.0, 1.0, 1.0, 0.0).p_see(1e-20) / (std::log(2.0) * 1e-20),
              1.0, 1e-12);
}

// --- binomial sampler ----------------------------------------------------------------------------

struct Moments {
  double mean = 0.0;
  double variance = 0.0;
};

Moments draw_moments(uint64_t n, double p, int draws, uint64_t seed) {
  Pcg32 rng(seed);
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < draws; ++i) {
    const auto x = static_cast<double>(draw_binomial(n, p, rng));
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / draws;
  return {mean, (sum2 - draws * mean * mean) / (draws - 1)};
}

TEST(PsychometricBinomialSampler, MeanAndVariance) {
  // Bounds of 5 standard errors: the mean's SE is sqrt(npq / N); the sample variance's is about
  // npq * sqrt(2 / N) (plus a small excess-kurtosis term, covered by the margin), so a correct
  // sampler fails with probability below 1e-6 per check.
  struct Case {
    uint64_t n;
    double p;
    int draws;
  };
  for (const Case c : {Case{1, 0.3, 20000}, Case{20, 0.3, 20000}, Case{64, 0.9, 20000}, Case{65, 0.5, 20000},
                       Case{1000, 0.002, 20000}, Case{100000, 0.37, 10000}, Case{1000000, 0.9999, 10000}}) {
    const double n = static_cast<double>(c.n);
    const double variance = n * c.p * (1 - c.p);
    const Moments m = draw_moments(c.n, c.p, c.draws, derive_seed(99, c.n));
    SCOPED_TRACE("n = " + std::to_string(c.n) + ", p = " + std::to_string(c.p));
    EXPECT_NEAR(m.mean, n * c.p, 5.0 * std::sqrt(variance / c.draws));
    EXPECT_NEAR(m.variance, variance, 5.0 * variance * std::sqrt(3.0 / c.draws));
  }
}

TEST(PsychometricBinomialSampler, DegenerateProbabilitiesAreExact) {
  Pcg32 rng(1);
  for (uint64_t n : {1ull, 7ull, 64ull, 65ull, 1000000ull}) {
    EXPECT_EQ(draw_binomial(n, 0.0, rng), 0u);
    EXPECT_EQ(draw_binomial(n, 1.0, rng), n);
  }
  EXPECT_EQ(draw_binomial(0, 0.5, rng), 0u);
  EXPECT_THROW(draw_binomial(10, std::nan(""), rng), std::invalid_argument);
}

TEST(PsychometricBinomialSampler, InversionIsExactForLargeN) {
  // For n > 64 a draw is the integer x with P(X <= x - 1) < u <= P(X <= x) for the one uniform u
  // it takes from the generator.
  for (const auto& [n, p] : std::vector<std::pair<uint64_t, double>>{{65, 0.5}, {500, 0.03}, {123456, 0.71}}) {
    const boost::math::binomial_distribution<double> dist(static_cast<double>(n), p);
    Pcg32 rng(derive_seed(5, n));
    for (int i = 0; i < 2000; ++i) {
      Pcg32 copy = rng;
      const double u = copy.uniform();
      const uint64_t x = draw_binomial(n, p, rng);
      ASSERT_LE(x, n);
      EXPECT_LE(u, boost::math::cdf(dist, static_cast<double>(x))) << n << " " << u;
      if (x > 0) {
        EXPECT_LT(boost::math::cdf(dist, static_cast<double>(x) - 1.0), u) << n << " " << u;
      }
      // The generator moved by exactly one uniform.
      EXPECT_EQ(copy.next_u32(), Pcg32(rng).next_u32());
    }
  }
}

TEST(PsychometricBinomialSampler, HistogramMatchesTheDistribution) {
  // Pearson chi-square over the outcomes with expected count >= 20 (pooled tails), for one n of
  // each method. With about 25 degrees of freedom, df + 8 sqrt(2 df) is exceeded with probability
  // well below 1e-6 by a correct sampler; an off-by-one in the inversion gives thousands.
  for (uint64_t n : {40ull, 200ull}) {
    const double p = 0.35;
    const boost::math::binomial_distribution<double> dist(static_cast<double>(n), p);
    const int draws = 40000;
    std::vector<double> counts(n + 1, 0.0);
    Pcg32 rng(derive_seed(17, n));
    for (int i = 0; i < draws; ++i) counts[draw_binomial(n, p, rng)] += 1.0;
    double chi2 = 0.0, pooled_expected = 0.0, pooled_observed = 0.0;
    int cells = 0;
    for (uint64_t x = 0; x <= n; ++x) {
      const double expected = draws * boost::math::pdf(dist, static_cast<double>(x));
      if (expected >= 20.0) {
        chi2 += (counts[x] - expected) * (counts[x] - expected) / expected;
        ++cells;
      } else {
        pooled_expected += expected;
        pooled_observed += counts[x];
      }
    }
    chi2 += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
    const double df = cells;  // cells + pooled cell - 1
    EXPECT_LT(chi2, df + 8.0 * std::sqrt(2.0 * df)) << "n = " << n;
  }
}

// --- maximum-likelihood fits ----------------------------------------------------------------------

TEST(PsychometricFit, RecoversKnownModelsFromExpectedCounts) {
  for (PsychometricShape shape : kShapes) {
    for (bool rising : {true, false}) {
      for (double guess : {0.0, 0.5}) {
        const bool weibull = shape == PsychometricShape::weibull;
        // Weibull on a log-spaced axis 0.25..4 with threshold 1.3; the others on 0..4 with threshold 2.2.
        std::vector<double> levels;
        for (int i = 0; i < 9; ++i) levels.push_back(weibull ? 0.25 * std::pow(2.0, i * 0.5) : 0.5 * i);
        const double threshold = weibull ? 1.3 : 2.2;
        const double slope = weibull ? 2.5 : 1.7;
        const double lapse = 0.03;
        const PsychometricModel truth = make_model(shape, rising, guess, threshold, slope, lapse);
        FitOptions options;
        options.shape = shape;
        options.rising = rising;
        options.guess = guess;
        options.max_lapse = 0.08;
        options.bootstrap_samples = 0;
        const std::vector<LevelCounts> data = expected_counts(truth, levels, 1000000);
        const PsychometricFit fit = fit_psychometric(data, options);
        SCOPED_TRACE(std::string(shape_name(shape)) + (rising ? " rising" : " falling") + " guess " +
                     std::to_string(guess));
        EXPECT_TRUE(fit.converged) << fit.note;
        EXPECT_EQ(fit.model.shape, shape);
        EXPECT_EQ(fit.model.rising, rising);
        EXPECT_EQ(fit.model.guess, guess);
        EXPECT_NEAR(fit.model.parameters.threshold, threshold, 2e-3 * threshold);
        EXPECT_NEAR(fit.model.parameters.slope, slope, 5e-3 * slope);
        EXPECT_NEAR(fit.model.parameters.lapse, lapse, 1e-3);
        // The true model is in the family: the fit is at least as likely, and nearly saturated.
        EXPECT_GE(fit.log_likelihood, log_likelihood(data, truth) - 1e-6);
        EXPECT_NEAR(fit.log_likelihood, log_likelihood(data, fit.model), 1e-6 * std::fabs(fit.log_likelihood));
        EXPECT_LT(fit.deviance, 0.1);
        EXPECT_EQ(fit.degrees_of_freedom, 6);
        EXPECT_TRUE(std::isnan(fit.bootstrap_threshold_interval.lower));
        EXPECT_TRUE(std::isnan(fit.deviance_p_value));
        EXPECT_EQ(fit.note, "");
      }
    }
  }
}

TEST(PsychometricFit, MatchesIndependentScipyReference) {
  // Fixture made by tests/analysis/fitting/make_scipy_reference.py (SciPy 1.10.1,
  // NumPy 1.24.2, Python 3.11.2: see the file for the optimiser).
  std::ifstream in(std::string(FOVLAB_SOURCE_DIR) + "/tests/analysis/fitting/scipy_reference.json");
  ASSERT_TRUE(in) << "missing fixture";
  const nlohmann::json reference = nlohmann::json::parse(in);
  ASSERT_EQ(reference.at("cases").size(), 3u);
  for (const nlohmann::json& c : reference.at("cases")) {
    SCOPED_TRACE(c.at("name").get<std::string>());
    const std::string shape = c.at("shape");
    FitOptions options;
    options.shape = shape == "logistic"  ? PsychometricShape::logistic
                    : shape == "weibull" ? PsychometricShape::weibull
                                         : PsychometricShape::cumulative_normal;
    options.rising = c.at("rising");
    options.guess = c.at("guess");
    options.max_lapse = c.at("max_lapse");
    options.bootstrap_samples = 0;
    std::vector<LevelCounts> data;
    for (size_t i = 0; i < c.at("levels").size(); ++i)
      data.push_back({c.at("levels")[i].get<double>(), c.at("n")[i].get<uint64_t>(), c.at("k")[i].get<uint64_t>()});
    const nlohmann::json& expected = c.at("fit");
    const PsychometricFit fit = fit_psychometric(data, options);
    EXPECT_TRUE(fit.converged);
    EXPECT_GE(fit.log_likelihood, expected.at("log_likelihood").get<double>() - 1e-6);
    EXPECT_NEAR(fit.log_likelihood, expected.at("log_likelihood").get<double>(), 1e-5);
    const double threshold = expected.at("threshold");
    EXPECT_NEAR(fit.model.parameters.threshold, threshold, 1e-3 * threshold);
    EXPECT_NEAR(fit.model.parameters.slope, expected.at("slope").get<double>(),
                2e-3 * expected.at("slope").get<double>());
    EXPECT_NEAR(fit.model.parameters.lapse, expected.at("lapse").get<double>(), 1e-4);
    EXPECT_NEAR(fit.deviance, 2.0 * (saturated_log_likelihood(data) - fit.log_likelihood), 1e-9);
    EXPECT_EQ(fit.degrees_of_freedom, 3);
    // The profile-likelihood interval, computed by SciPy with its own inner fits and root finder.
    const nlohmann::json& profile = c.at("threshold_profile_interval");
    EXPECT_EQ(profile.at("confidence").get<double>(), options.confidence);
    EXPECT_NEAR(fit.threshold_interval.lower, profile.at("lower").get<double>(), 1e-7 * threshold);
    EXPECT_NEAR(fit.threshold_interval.upper, profile.at("upper").get<double>(), 1e-7 * threshold);
  }
}

// --- profile-likelihood intervals -----------------------------------------------------------------

TEST(PsychometricProfile, ContainsTheEstimateWhereTheBootstrapDoesNot) {
  // Issue 18's case: the answers step between two adjacent levels, so the slope is unbounded and the
  // threshold is anywhere between them. Replicate fits put it elsewhere in the gap than the fit did,
  // so the percentile interval may miss the estimate; the profile interval cannot.
  const std::vector<LevelCounts> data = {{4, 10, 0}, {8, 10, 0}, {16, 10, 0}, {32, 10, 10}, {64, 10, 10}};
  for (PsychometricShape shape : kShapes) {
    SCOPED_TRACE(shape_name(shape));
    FitOptions options;
    options.shape = shape;
    options.bootstrap_samples = 200;
    const PsychometricFit fit = fit_psychometric(data, options);
    const double estimate = fit.model.parameters.threshold;
    EXPECT_LE(fit.threshold_interval.lower, estimate);
    EXPECT_GE(fit.threshold_interval.upper, estimate);
    // The data place the threshold between 16 and 32 (an unbounded slope makes the gap's ends
    // themselves just reachable), and leave the slope unbounded above.
    EXPECT_GE(fit.threshold_interval.lower, 15.9);
    EXPECT_LE(fit.threshold_interval.upper, 32.1);
    EXPECT_EQ(fit.slope_interval.upper, std::numeric_limits<double>::infinity());
    EXPECT_NE(fit.note.find("profile-likelihood interval of the slope is unbounded above"), std::string::npos)
        << fit.note;
  }
}

TEST(PsychometricProfile, EndsSitOnTheLikelihoodRatioCut) {
  // At each end of the interval, the best fit with the threshold held there (an independent grid
  // over slope and lapse, refined) is worse than the fit by chi2(0.95, 1) / 2 = 1.9207 in log L.
  const std::vector<LevelCounts> data = {{0.5, 30, 2},  {1.0, 30, 4},  {1.5, 30, 9}, {2.0, 30, 12},
                                         {2.5, 30, 21}, {3.0, 30, 17}, {3.5, 30, 28}};
  FitOptions options;
  options.max_lapse = 0.06;
  options.bootstrap_samples = 0;
  const PsychometricFit fit = fit_psychometric(data, options);
  const auto profile = [&](double threshold) {
    double best = -std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 400; ++i)
      for (int j = 0; j <= 60; ++j) {
        PsychometricModel m = fit.model;
        m.parameters.threshold = threshold;
        m.parameters.slope = std::exp(std::log(0.1) + (std::log(40.0) - std::log(0.1)) * i / 400.0);
        m.parameters.lapse = 0.06 * j / 60.0;
        best = std::max(best, log_likelihood(data, m));
      }
    return best;
  };
  const double cut = 0.5 * 3.841458820694124;
  for (double end : {fit.threshold_interval.lower, fit.threshold_interval.upper}) {
    EXPECT_NEAR(fit.log_likelihood - profile(end), cut, 2e-3);
  }
  EXPECT_LT(fit.threshold_interval.lower, fit.model.parameters.threshold);
  EXPECT_GT(fit.threshold_interval.upper, fit.model.parameters.threshold);
  EXPECT_LE(fit.lapse_interval.lower, fit.model.parameters.lapse);
  EXPECT_GE(fit.lapse_interval.upper, fit.model.parameters.lapse);
  EXPECT_LT(fit.slope_interval.lower, fit.model.parameters.slope);
  EXPECT_GT(fit.slope_interval.upper, fit.model.parameters.slope);
  // A narrower confidence gives a narrower interval inside the wider one.
  options.confidence = 0.5;
  const PsychometricFit narrow = fit_psychometric(data, options);
  EXPECT_GT(narrow.threshold_interval.lower, fit.threshold_interval.lower);
  EXPECT_LT(narrow.threshold_interval.upper, fit.threshold_interval.upper);
}

TEST(PsychometricProfile, UnboundedWhereTheDataSayNothing) {
  // Every level at floor: the threshold lies beyond the most intense level; how far, nothing says.
  std::vector<LevelCounts> data;
  for (double level : {1.0, 2.0, 3.0, 4.0}) data.push_back({level, 20, 0});
  FitOptions options;
  options.bootstrap_samples = 0;
  const PsychometricFit fit = fit_psychometric(data, options);
  EXPECT_EQ(fit.threshold_interval.upper, std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isfinite(fit.threshold_interval.lower));
  EXPECT_GT(fit.threshold_interval.lower, 3.0);
  EXPECT_NE(fit.note.find("profile-likelihood interval of the threshold is unbounded above"), std::string::npos)
      << fit.note;
}

TEST(PsychometricFit, LevelOrderDoesNotMatter) {
  const std::vector<LevelCounts> sorted = {{1, 30, 3}, {2, 30, 9}, {3, 30, 17}, {4, 30, 25}, {5, 30, 28}};
  const std::vector<LevelCounts> shuffled = {{4, 30, 25}, {1, 30, 3}, {5, 30, 28}, {3, 30, 17}, {2, 30, 9}};
  FitOptions options;
  options.bootstrap_samples = 50;
  const PsychometricFit a = fit_psychometric(sorted, options);
  const PsychometricFit b = fit_psychometric(shuffled, options);
  EXPECT_EQ(a.model.parameters.threshold, b.model.parameters.threshold);
  EXPECT_EQ(a.model.parameters.slope, b.model.parameters.slope);
  EXPECT_EQ(a.model.parameters.lapse, b.model.parameters.lapse);
  EXPECT_EQ(a.threshold_interval.lower, b.threshold_interval.lower);
  EXPECT_EQ(a.deviance_p_value, b.deviance_p_value);
}

TEST(PsychometricFit, AllAtFloorOrCeiling) {
  const std::vector<double> levels = {1, 2, 3, 4, 5, 6};
  for (PsychometricShape shape : kShapes) {
    for (bool ceiling : {false, true}) {
      std::vector<LevelCounts> data;
      for (double level : levels) data.push_back({level, 25, ceiling ? 25u : 0u});
      FitOptions options;
      options.shape = shape;
      options.bootstrap_samples = 20;
      const PsychometricFit fit = fit_psychometric(data, options);
      SCOPED_TRACE(std::string(shape_name(shape)) + (ceiling ? " ceiling" : " floor"));
      EXPECT_TRUE(finite_model(fit.model));
      EXPECT_NE(fit.note.find(ceiling ? "every level at ceiling" : "every level at floor"), std::string::npos)
          << fit.note;
      // The fit reproduces the data: p_report near 0 (or 1 - lapse, with the lapse at 0) everywhere.
      for (double level : levels) EXPECT_NEAR(fit.model.p_report(level), ceiling ? 1.0 : 0.0, 1e-3);
      EXPECT_NEAR(fit.deviance, 0.0, 1e-3);
      EXPECT_TRUE(std::isfinite(fit.bootstrap_threshold_interval.lower) &&
                  std::isfinite(fit.bootstrap_threshold_interval.upper));
    }
  }
}

TEST(PsychometricFit, FlatDataAtHalf) {
  std::vector<LevelCounts> data;
  for (int i = 0; i < 6; ++i) data.push_back({static_cast<double>(i), 40, 20});
  for (PsychometricShape shape : {PsychometricShape::logistic, PsychometricShape::cumulative_normal}) {
    FitOptions options;
    options.shape = shape;
    options.bootstrap_samples = 0;
    const PsychometricFit fit = fit_psychometric(data, options);
    EXPECT_TRUE(finite_model(fit.model));
    for (const LevelCounts& d : data) EXPECT_NEAR(fit.model.p_report(d.level), 0.5, 1e-3);
    EXPECT_NEAR(fit.deviance, 0.0, 1e-4);
    EXPECT_NEAR(fit.log_likelihood, saturated_log_likelihood(data), 1e-4);
    EXPECT_NE(fit.note, "");
  }
  // With guess 0.5, p_report = 1/2 means p_see = 0: the threshold is beyond the tested levels.
  FitOptions two_afc;
  two_afc.guess = 0.5;
  two_afc.bootstrap_samples = 0;
  const PsychometricFit fit = fit_psychometric(data, two_afc);
  EXPECT_TRUE(finite_model(fit.model));
  EXPECT_GT(fit.model.parameters.threshold, 5.0);
  for (const LevelCounts& d : data) EXPECT_NEAR(fit.model.p_report(d.level), 0.5, 1e-3);
  EXPECT_NE(fit.note.find("threshold outside the tested levels"), std::string::npos) << fit.note;
}

TEST(PsychometricFit, TwoLevels) {
  const std::vector<LevelCounts> data = {{1.0, 30, 6}, {3.0, 30, 24}};
  for (PsychometricShape shape : kShapes) {
    FitOptions options;
    options.shape = shape;
    options.bootstrap_samples = 20;
    const PsychometricFit fit = fit_psychometric(data, options);
    SCOPED_TRACE(shape_name(shape));
    EXPECT_TRUE(finite_model(fit.model));
    EXPECT_NE(fit.note.find("only two levels"), std::string::npos) << fit.note;
    EXPECT_EQ(fit.degrees_of_freedom, -1);
    EXPECT_NEAR(fit.model.p_report(1.0), 0.2, 1e-4);  // two points, three parameters: saturated
    EXPECT_NEAR(fit.model.p_report(3.0), 0.8, 1e-4);
  }
}

TEST(PsychometricFit, FixedZeroLapse) {
  const std::vector<LevelCounts> data = {{1, 30, 3}, {2, 30, 9}, {3, 30, 17}, {4, 30, 25}, {5, 30, 30}};
  FitOptions options;
  options.max_lapse = 0.0;
  options.bootstrap_samples = 20;
  const PsychometricFit fit = fit_psychometric(data, options);
  EXPECT_TRUE(fit.converged);
  EXPECT_EQ(fit.model.parameters.lapse, 0.0);
  EXPECT_EQ(fit.lapse_interval.lower, 0.0);
  EXPECT_EQ(fit.lapse_interval.upper, 0.0);
  FitOptions free = options;
  free.max_lapse = 0.1;
  EXPECT_GE(fit_psychometric(data, free).log_likelihood, fit.log_likelihood - 1e-9);
}

TEST(PsychometricFit, RejectsBadInput) {
  const std::vector<LevelCounts> good = {{1, 10, 2}, {2, 10, 5}, {3, 10, 8}};
  FitOptions options;
  options.bootstrap_samples = 0;
  EXPECT_NO_THROW(fit_psychometric(good, options));
  EXPECT_THROW(fit_psychometric({}, options), std::invalid_argument);
  EXPECT_THROW(fit_psychometric({{1, 10, 2}, {2, 0, 0}, {3, 10, 8}}, options), std::invalid_argument);
  EXPECT_THROW(fit_psychometric({{1, 10, 2}, {2, 10, 11}, {3, 10, 8}}, options), std::invalid_argument);
  EXPECT_THROW(fit_psychometric({{1, 10, 2}, {std::nan(""), 10, 5}, {3, 10, 8}}, options), std::invalid_argument);
  EXPECT_THROW(fit_psychometric({{1, 10, 2}, {INFINITY, 10, 5}}, options), std::invalid_argument);
  EXPECT_THROW(fit_psychometric({{2, 10, 2}, {2, 10, 5}}, options), std::invalid_argument);  // one level
  FitOptions weibull = options;
  weibull.shape = PsychometricShape::weibull;
  EXPECT_NO_THROW(fit_psychometric(good, weibull));
  EXPECT_THROW(fit_psychometric({{0, 10, 2}, {2, 10, 5}, {3, 10, 8}}, weibull), std::invalid_argument);
  EXPECT_THROW(fit_psychometric({{-1, 10, 2}, {2, 10, 5}, {3, 10, 8}}, weibull), std::invalid_argument);
  const auto with = [&](auto change) {
    FitOptions o = options;
    change(o);
    return o;
  };
  EXPECT_THROW(fit_psychometric(good, with([](FitOptions& o) { o.guess = -0.1; })), std::invalid_argument);
  EXPECT_THROW(fit_psychometric(good, with([](FitOptions& o) { o.guess = 1.0; })), std::invalid_argument);
  EXPECT_THROW(fit_psychometric(good, with([](FitOptions& o) { o.max_lapse = -0.01; })), std::invalid_argument);
  EXPECT_THROW(fit_psychometric(good, with([](FitOptions& o) { o.guess = 0.5, o.max_lapse = 0.5; })),
               std::invalid_argument);
  EXPECT_THROW(fit_psychometric(good, with([](FitOptions& o) { o.bootstrap_samples = -1; })), std::invalid_argument);
  EXPECT_THROW(fit_psychometric(good, with([](FitOptions& o) { o.confidence = 1.0; })), std::invalid_argument);
  EXPECT_THROW(fit_psychometric(good, with([](FitOptions& o) { o.confidence = 0.0; })), std::invalid_argument);
  EXPECT_THROW(fit_psychometric(good, with([](FitOptions& o) { o.shape = static_cast<PsychometricShape>(7); })),
               std::invalid_argument);
}

// --- bootstrap ----------------------------------------------------------------------------------

const std::vector<double> kBootstrapLevels = {0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5};

TEST(PsychometricBootstrap, ReplaysFromTheSeed) {
  const PsychometricModel truth = make_model(PsychometricShape::logistic, true, 0.0, 2.0, 2.0, 0.02);
  const std::vector<LevelCounts> data = simulate(truth, kBootstrapLevels, 40, 2024);
  FitOptions options;
  options.max_lapse = 0.06;
  options.bootstrap_samples = 200;
  options.seed = 7;
  const PsychometricFit a = fit_psychometric(data, options);
  const PsychometricFit b = fit_psychometric(data, options);
  options.seed = 8;
  const PsychometricFit c = fit_psychometric(data, options);
  EXPECT_EQ(a.bootstrap_samples + a.bootstrap_failures, 200);
  EXPECT_GE(a.bootstrap_samples, 190);
  for (const auto& [x, y] : {std::pair{a.bootstrap_threshold_interval, b.bootstrap_threshold_interval},
                             std::pair{a.bootstrap_slope_interval, b.bootstrap_slope_interval},
                             std::pair{a.bootstrap_lapse_interval, b.bootstrap_lapse_interval}}) {
    EXPECT_EQ(x.lower, y.lower);
    EXPECT_EQ(x.upper, y.upper);
  }
  EXPECT_EQ(a.deviance_p_value, b.deviance_p_value);
  EXPECT_NE(a.bootstrap_threshold_interval.lower, c.bootstrap_threshold_interval.lower);
  EXPECT_NE(a.bootstrap_threshold_interval.upper, c.bootstrap_threshold_interval.upper);
  // The ML estimates do not depend on the seed.
  EXPECT_EQ(a.model.parameters.threshold, c.model.parameters.threshold);
  // The intervals bracket the estimates and the truth.
  EXPECT_LT(a.bootstrap_threshold_interval.lower, a.model.parameters.threshold);
  EXPECT_GT(a.bootstrap_threshold_interval.upper, a.model.parameters.threshold);
  EXPECT_LT(a.bootstrap_threshold_interval.lower, 2.0);
  EXPECT_GT(a.bootstrap_threshold_interval.upper, 2.0);
  EXPECT_LT(a.bootstrap_slope_interval.lower, a.bootstrap_slope_interval.upper);
  EXPECT_GE(a.bootstrap_lapse_interval.lower, 0.0);
  EXPECT_LE(a.bootstrap_lapse_interval.upper, 0.06);
  EXPECT_GT(a.deviance_p_value, 0.0);
  EXPECT_LE(a.deviance_p_value, 1.0);
  // Narrower confidence, narrower interval.
  options.seed = 7;
  options.confidence = 0.5;
  const PsychometricFit narrow = fit_psychometric(data, options);
  EXPECT_GT(narrow.bootstrap_threshold_interval.lower, a.bootstrap_threshold_interval.lower);
  EXPECT_LT(narrow.bootstrap_threshold_interval.upper, a.bootstrap_threshold_interval.upper);
}

// Type-7 percentile (linear interpolation between order statistics), as documented.
double percentile_of(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double h = (static_cast<double>(values.size()) - 1.0) * q;
  const auto i = static_cast<size_t>(std::floor(h));
  const size_t j = std::min(i + 1, values.size() - 1);
  return values[i] + (h - static_cast<double>(i)) * (values[j] - values[i]);
}

TEST(PsychometricBootstrap, ReplicatesFollowTheDocumentedRecipe) {
  // Rebuild every replicate from (seed, b) alone: Pcg32(derive_seed(seed, b)), one binomial draw per
  // level in increasing level order from the fitted p_report, then an ML fit of its own. The
  // percentile intervals and the deviance p-value must agree with fit_psychometric's (up to the
  // optimiser's tolerance: the replicate fits here start from the grid, not from the ML fit).
  const std::vector<LevelCounts> data = {{3.0, 30, 17}, {0.5, 30, 2},  {1.0, 30, 4}, {1.5, 30, 9},
                                         {2.5, 30, 21}, {2.0, 30, 12}, {3.5, 30, 28}};  // unsorted on purpose
  FitOptions options;
  options.max_lapse = 0.06;
  options.bootstrap_samples = 60;
  options.seed = 4242;
  options.confidence = 0.8;
  const PsychometricFit fit = fit_psychometric(data, options);
  ASSERT_EQ(fit.bootstrap_samples, 60);
  std::vector<LevelCounts> sorted = data;
  std::sort(sorted.begin(), sorted.end(), [](const LevelCounts& a, const LevelCounts& b) { return a.level < b.level; });
  std::vector<double> thresholds, slopes, lapses, deviances;
  FitOptions replicate_options = options;
  replicate_options.bootstrap_samples = 0;
  for (int b = 0; b < 60; ++b) {
    Pcg32 rng(derive_seed(options.seed, static_cast<uint64_t>(b)));
    std::vector<LevelCounts> replicate;
    for (const LevelCounts& d : sorted)
      replicate.push_back({d.level, d.n, draw_binomial(d.n, fit.model.p_report(d.level), rng)});
    const PsychometricFit r = fit_psychometric(replicate, replicate_options);
    thresholds.push_back(r.model.parameters.threshold);
    slopes.push_back(r.model.parameters.slope);
    lapses.push_back(r.model.parameters.lapse);
    deviances.push_back(r.deviance);
  }
  EXPECT_NEAR(fit.bootstrap_threshold_interval.lower, percentile_of(thresholds, 0.1), 1e-4);
  EXPECT_NEAR(fit.bootstrap_threshold_interval.upper, percentile_of(thresholds, 0.9), 1e-4);
  EXPECT_NEAR(fit.bootstrap_slope_interval.lower, percentile_of(slopes, 0.1), 1e-3);
  EXPECT_NEAR(fit.bootstrap_slope_interval.upper, percentile_of(slopes, 0.9), 1e-3);
  EXPECT_NEAR(fit.bootstrap_lapse_interval.lower, percentile_of(lapses, 0.1), 1e-4);
  EXPECT_NEAR(fit.bootstrap_lapse_interval.upper, percentile_of(lapses, 0.9), 1e-4);
  const auto at_least = std::count_if(deviances.begin(), deviances.end(), [&](double d) { return d >= fit.deviance; });
  EXPECT_NEAR(fit.deviance_p_value, static_cast<double>(at_least) / 60.0, 1.0 / 60.0 + 1e-12);
  EXPECT_GT(fit.deviance_p_value, 0.0);
  EXPECT_LT(fit.deviance_p_value, 1.0);
}

TEST(PsychometricBootstrap, DevianceFlagsAModelThatDoesNotFit) {
  // A non-monotonic data set no sigmoid can follow: the deviance is far above every replicate's.
  const std::vector<LevelCounts> bad = {{1, 100, 5},  {2, 100, 90}, {3, 100, 10},
                                        {4, 100, 95}, {5, 100, 50}, {6, 100, 99}};
  FitOptions options;
  options.bootstrap_samples = 100;
  const PsychometricFit fit = fit_psychometric(bad, options);
  EXPECT_GT(fit.deviance, 100.0);
  EXPECT_EQ(fit.deviance_p_value, 0.0);
}

TEST(PsychometricBootstrap, LargeCountsStayFast) {
  // n = 10^6 per level: the sampler inverts one uniform per level instead of summing 10^6.
  const PsychometricModel truth = make_model(PsychometricShape::cumulative_normal, false, 0.0, 20.0, 0.1, 0.01);
  const std::vector<LevelCounts> data = simulate(truth, {5, 10, 15, 20, 25, 30, 35}, 1000000, 3);
  FitOptions options;
  options.shape = PsychometricShape::cumulative_normal;
  options.rising = false;
  options.bootstrap_samples = 50;
  const PsychometricFit fit = fit_psychometric(data, options);
  EXPECT_EQ(fit.bootstrap_samples, 50);
  EXPECT_LT(fit.bootstrap_threshold_interval.lower, 20.0);
  EXPECT_GT(fit.bootstrap_threshold_interval.upper, 20.0);
  EXPECT_LT(fit.bootstrap_threshold_interval.upper - fit.bootstrap_threshold_interval.lower, 0.1);
}

TEST(PsychometricIntervals, CoverageOfTheThresholdIntervals) {
  // 40 simulated experiments (7 levels x 40 trials, seeds from a Pcg32), each with a 95 % profile-
  // likelihood interval and a 95 % percentile interval from 100 bootstrap replicates. The number of
  // intervals containing the true threshold is Binomial(40, c) for the true coverage c of the method.
  // - Profile: the likelihood-ratio statistic is close to chi-square here (280 trials), so c should
  //   be near 0.95 (38 of 40 with these seeds). >= 34 fails a method with c = 0.95 with probability
  //   3 %, one with c = 0.5 essentially never. It always holds the estimate.
  // - Percentile: under-covers a little at these sample sizes (cf. Wichmann & Hill 2001b): c was
  //   about 0.91 over 160 such experiments with other seeds (37 of 40 with these). >= 30 fails a
  //   correct method with probability 0.6 % at c = 0.88, and passes one with c = 0.5 with 0.1 %.
  // The run is deterministic; the bounds only guard against changed seeds or details.
  const PsychometricModel truth = make_model(PsychometricShape::logistic, true, 0.0, 2.0, 2.0, 0.02);
  Pcg32 seeds(20240601);
  int profile_covered = 0, bootstrap_covered = 0;
  double profile_width = 0.0, bootstrap_width = 0.0;
  for (int experiment = 0; experiment < 40; ++experiment) {
    const std::vector<LevelCounts> data = simulate(truth, kBootstrapLevels, 40, seeds.next_u32());
    FitOptions options;
    options.max_lapse = 0.06;
    options.bootstrap_samples = 100;
    options.seed = seeds.next_u32();
    const PsychometricFit fit = fit_psychometric(data, options);
    const ParameterInterval& profile = fit.threshold_interval;
    const ParameterInterval& bootstrap = fit.bootstrap_threshold_interval;
    EXPECT_LE(profile.lower, fit.model.parameters.threshold);
    EXPECT_GE(profile.upper, fit.model.parameters.threshold);
    profile_covered += profile.lower <= 2.0 && 2.0 <= profile.upper;
    bootstrap_covered += bootstrap.lower <= 2.0 && 2.0 <= bootstrap.upper;
    profile_width += profile.upper - profile.lower;
    bootstrap_width += bootstrap.upper - bootstrap.lower;
  }
  EXPECT_GE(profile_covered, 34);
  EXPECT_GE(bootstrap_covered, 30);
  // Neither too wide nor too narrow: the ML threshold's standard deviation over such experiments
  // is about 0.105, so a normal 95 % interval would span 0.41; the profile intervals average 0.39,
  // the percentile intervals 0.35 (their under-coverage above). Half or twice as wide fails.
  EXPECT_GT(profile_width / 40, 0.3);
  EXPECT_LT(profile_width / 40, 0.6);
  EXPECT_GT(bootstrap_width / 40, 0.25);
  EXPECT_LT(bootstrap_width / 40, 0.6);
}

}  // namespace
}  // namespace fovlab::analysis
