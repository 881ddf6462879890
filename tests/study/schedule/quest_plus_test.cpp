// Tests of study/schedule/quest_plus.h: every choice, expected entropy and posterior summary against
// a brute-force NumPy implementation (make_quest_plus_reference.py), replay from answers, and the
// rule's bad values.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "study/schedule/quest_plus.h"

namespace fovlab {
namespace {

std::vector<double> numbers(const nlohmann::json& array) { return array.get<std::vector<double>>(); }

QuestPlusRule rule_of(const nlohmann::json& c) {
  QuestPlusRule rule;
  const std::string shape = c["shape"];
  rule.shape = shape == "logistic"  ? PsychometricShape::logistic
               : shape == "weibull" ? PsychometricShape::weibull
                                    : PsychometricShape::cumulative_normal;
  rule.rising = c["rising"];
  rule.guess = c["guess"];
  rule.thresholds = numbers(c["thresholds"]);
  rule.slopes = numbers(c["slopes"]);
  rule.lapses = numbers(c["lapses"]);
  rule.prior_mean = c["prior_mean"];
  rule.prior_sd = c["prior_sd"];
  rule.max_trials = c["trials"];
  return rule;
}

void expect_close(double actual, double expected, const std::string& what) {
  EXPECT_LE(std::abs(actual - expected), 1e-9 * std::max(1.0, std::abs(expected)))
      << what << ": " << actual << " vs " << expected;
}

TEST(QuestPlus, EveryChoiceAndPosteriorMatchesABruteForceNumpyReference) {
  std::ifstream in(std::string(FOVLAB_SOURCE_DIR) + "/tests/study/schedule/quest_plus_reference.json");
  ASSERT_TRUE(in) << "missing fixture";
  const nlohmann::json reference = nlohmann::json::parse(in);
  ASSERT_EQ(reference["cases"].size(), 3u);
  for (const nlohmann::json& c : reference["cases"]) {
    SCOPED_TRACE(c["name"].get<std::string>());
    const QuestPlusRule rule = rule_of(c);
    const std::vector<double> levels = numbers(c["levels"]);
    ASSERT_FALSE(quest_plus_rule_error(rule, levels));
    const QuestPlus quest(rule, levels);
    QuestPlusState state = quest.start();
    std::vector<bool> answers;
    int step_number = 0;
    for (const nlohmann::json& step : c["steps"]) {
      const std::string at = "step " + std::to_string(step_number++);
      const std::vector<double> expected = numbers(step["expected_entropies"]);
      const std::vector<double> entropies = quest.expected_entropies(state.posterior);
      ASSERT_EQ(entropies.size(), expected.size());
      for (size_t x = 0; x < expected.size(); ++x)
        expect_close(entropies[x], expected[x], at + " E[H] of level " + std::to_string(x));
      ASSERT_EQ(state.index, step["index"].get<int>()) << at;
      ASSERT_FALSE(state.finished) << at;
      const bool seen = step["seen"];
      answers.push_back(seen);
      state = quest.next(state, seen);
      const QuestPlusEstimate estimate = quest.estimate(state.posterior);
      expect_close(estimate.threshold_mean, step["threshold_mean"], at + " threshold mean");
      expect_close(estimate.threshold_lower, step["threshold_lower"], at + " interval lower");
      expect_close(estimate.threshold_upper, step["threshold_upper"], at + " interval upper");
      expect_close(estimate.entropy_bits, step["entropy_bits"], at + " entropy");
    }
    EXPECT_TRUE(state.finished);  // max_trials
    // The same state again from the answers alone (resume and replay).
    const QuestPlusState again = quest.replay(answers);
    EXPECT_EQ(again.posterior, state.posterior);
    EXPECT_EQ(again.trials, state.trials);
  }
}

TEST(QuestPlus, ReproducesWatsonsFirstExample) {
  // Watson (2017), example 1, "Estimation of contrast threshold {1, 1, 2}": contrasts and thresholds
  // -40..0 dB, a Weibull in dB with slope 3.5, guess 0.5, lapse 0.02, and the published answers;
  // the contrasts chosen are the paper's (as the questplus and PsychoPy packages' tests list them),
  // and the posterior's mode is -20 dB. Watson's Weibull in dB, 1 - exp(-10^(slope (c - t) / 20)),
  // is ours on the linear contrast x = 10^(c / 20) with the threshold (p_see = 1/2) at
  // 10^(t / 20) (ln 2)^(1 / slope).
  const double slope = 3.5;
  QuestPlusRule rule;
  rule.shape = PsychometricShape::weibull;
  rule.rising = true;
  rule.guess = 0.5;
  rule.slopes = {slope};
  rule.lapses = {0.02};
  std::vector<double> levels, thresholds_db;
  for (int db = -40; db <= 0; ++db) {
    levels.push_back(std::pow(10.0, db / 20.0));
    thresholds_db.push_back(db);
    rule.thresholds.push_back(std::pow(10.0, db / 20.0) * std::pow(std::log(2.0), 1.0 / slope));
  }
  rule.max_trials = 32;
  ASSERT_FALSE(quest_plus_rule_error(rule, levels));
  const std::vector<int> expected_db = {-18, -22, -25, -28, -30, -22, -13, -15, -16, -18, -19, -20, -21, -22, -23, -19,
                                        -20, -20, -18, -18, -19, -17, -17, -18, -18, -18, -19, -19, -19, -19, -19, -19};
  const std::string correct = "11110011111111011011011111111111";  // the paper's answers, 1: correct
  const QuestPlus quest(rule, levels);
  QuestPlusState state = quest.start();
  for (size_t trial = 0; trial < expected_db.size(); ++trial) {
    ASSERT_EQ(state.index - 40, expected_db[trial]) << "trial " << trial;
    state = quest.next(state, correct[trial] == '1');
  }
  const auto mode = std::max_element(state.posterior.begin(), state.posterior.end()) - state.posterior.begin();
  EXPECT_EQ(thresholds_db[size_t(mode)], -20.0);
  double mean_db = 0.0;
  for (size_t t = 0; t < thresholds_db.size(); ++t) mean_db += state.posterior[t] * thresholds_db[t];
  EXPECT_NEAR(mean_db, -20.39360311638961, 1e-9);  // the questplus package's posterior mean
}

TEST(QuestPlus, StopsByEntropyOrIntervalWidth) {
  QuestPlusRule rule;
  rule.rising = true;
  rule.guess = 0.5;
  const std::vector<double> levels = {1, 2, 3, 4, 5, 6, 7, 8};
  rule.thresholds = default_quest_thresholds(levels, rule.shape);
  rule.slopes = default_quest_slopes(levels, rule.shape);
  rule.lapses = default_quest_lapses();
  rule.max_trials = 500;
  rule.stop_interval_width = 1.0;
  ASSERT_FALSE(quest_plus_rule_error(rule, levels));
  const QuestPlus quest(rule, levels);
  QuestPlusState state = quest.start();
  // An observer who sees everything from level 5 up.
  while (!state.finished) state = quest.next(state, levels[size_t(state.index)] >= 5);
  const QuestPlusEstimate estimate = quest.estimate(state.posterior);
  EXPECT_LE(estimate.threshold_upper - estimate.threshold_lower, 1.0);
  EXPECT_LT(state.trials, 500);
  EXPECT_GT(estimate.threshold_mean, 4.0);
  EXPECT_LT(estimate.threshold_mean, 5.0);
}

TEST(QuestPlus, BadRulesAreNamedByTheirKey) {
  const std::vector<double> levels = {1, 2, 3, 4};
  QuestPlusRule good;
  good.thresholds = {1, 2, 3, 4};
  good.slopes = {1, 2};
  good.lapses = {0, 0.02};
  ASSERT_FALSE(quest_plus_rule_error(good, levels));
  const auto error = [&](auto change) {
    QuestPlusRule rule = good;
    change(rule);
    return quest_plus_rule_error(rule, levels).value_or("no error");
  };
  EXPECT_EQ(error([](QuestPlusRule& r) { r.thresholds = {2, 1}; }).rfind("thresholds:", 0), 0u);
  EXPECT_EQ(error([](QuestPlusRule& r) { r.slopes = {0, 1}; }).rfind("slopes:", 0), 0u);
  EXPECT_EQ(error([](QuestPlusRule& r) {
              r.lapses = {0, 0.6};
              r.guess = 0.5;
            }).rfind("lapses:", 0),
            0u);
  EXPECT_EQ(error([](QuestPlusRule& r) {
              r.prior_sd = 0.01;
              r.prior_mean = 100;
            }).rfind("prior_mean: expected a prior with mass", 0),
            0u);
  EXPECT_EQ(error([](QuestPlusRule& r) { r.stop_entropy_bits = 4; }).rfind("stop_entropy_bits:", 0),
            0u);  // log2(16) = 4
  EXPECT_EQ(error([](QuestPlusRule& r) { r.stop_interval_width = 3; }).rfind("stop_interval_width:", 0), 0u);
  EXPECT_EQ(error([](QuestPlusRule& r) {
              r.shape = PsychometricShape::weibull;
              r.thresholds = {0, 1};
            }).rfind("thresholds:", 0),
            0u);
  // Thresholds within the levels' range widened by 10 spans (1 to 4: -29 to 34), quoted as given.
  EXPECT_EQ(error([](QuestPlusRule& r) {
              r.thresholds = {-1e308, 1e308};
            }),
            "thresholds: expected values from -29 to 34 (the levels' range, 1 to 4, widened by 10 times its span on "
            "each side), got -1e+308");
  EXPECT_EQ(error([](QuestPlusRule& r) {
              r.thresholds = {1, 34.000001};
            }).rfind("thresholds: expected values from -29 to 34", 0),
            0u);
  EXPECT_NE(error([](QuestPlusRule& r) { r.thresholds = {1, 34.000001}; }).find("got 34.000001"), std::string::npos);
  EXPECT_EQ(error([](QuestPlusRule& r) { r.thresholds = {-29, 34}; }), "no error");
  EXPECT_EQ(error([](QuestPlusRule& r) {
              r.thresholds = std::vector<double>(2001, 0);
              for (size_t i = 0; i < 2001; ++i) r.thresholds[i] = double(i);
              r.slopes = {1, 2, 3, 4, 5};
            }).rfind("thresholds: expected at most 20000", 0),
            0u);
}

}  // namespace
}  // namespace fovlab
