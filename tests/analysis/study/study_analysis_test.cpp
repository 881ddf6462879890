// Threshold definitions per protocol on hand-made study data, where the answer is known by
// construction (docs/analysis.md, "Thresholds").
#include <gtest/gtest.h>

#include <map>
#include <utility>

#include "analysis/study/study_analysis.h"

namespace fovlab::analysis {
namespace {

StudyData study(const std::string& protocol, const std::string& question, std::vector<double> levels,
                bool higher_is_better = true) {
  StudyData data;
  data.study = "hand_made";
  data.protocol = find_protocol(protocol).value();
  data.question = find_two_afc_question(question).value_or(TwoAfcQuestion::same);
  data.level_parameter = "foveal_deg";
  data.levels = std::move(levels);
  data.higher_is_better = higher_is_better;
  return data;
}

// `count` comparison trials at `level` on `scene`, `in_favour` of them answered in favour of the test.
void add_comparisons(ParticipantData& participant, const std::string& protocol, const std::string& scene, double level,
                     int count, int in_favour) {
  for (int i = 0; i < count; ++i) {
    StudyTrial trial;
    trial.index = static_cast<int>(participant.trials.size());
    trial.scene = scene;
    trial.level = level;
    trial.condition = "level=" + std::to_string(level);
    trial.reference_first = i % 2 == 0;
    const bool favour = i < in_favour;
    if (protocol == "2afc-same") trial.answers = {favour ? "same" : "different"};
    if (protocol == "2afc-better" || protocol == "pair") {
      const bool test_first = !trial.reference_first;
      trial.answers = {(favour == test_first) ? "first" : "second"};
    }
    if (protocol == "rating") trial.answers = {favour ? "3" : "1"};
    participant.trials.push_back(trial);
  }
}

AnalysisOptions quick_options() {
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  return options;
}

const GroupThreshold& threshold_of(const AnalysisResult& result, const std::string& scene) {
  for (const GroupThreshold& threshold : result.thresholds)
    if (threshold.group.scene == scene) return threshold;
  throw std::runtime_error("no threshold for " + scene);
}

TEST(StudyAnalysis, SameDifferentThresholdIsTheLowestLevelFromWhichNothingIsDistinguished) {
  StudyData data = study("2afc", "same", {2.5, 5, 7.5, 10});
  ParticipantData participant;
  participant.participant = "P001";
  // 40 trials a level: 2.5 and 5 clearly distinguished (5 and 12 of 40 "same"), 7.5 and 10 not.
  add_comparisons(participant, "2afc-same", "temple", 2.5, 40, 5);
  add_comparisons(participant, "2afc-same", "temple", 5, 40, 12);
  add_comparisons(participant, "2afc-same", "temple", 7.5, 40, 18);  // 45 %: not significant
  add_comparisons(participant, "2afc-same", "temple", 10, 40, 30);
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_EQ(result.conditions.size(), 4u);
  EXPECT_EQ(result.conditions[0].k, 5u);
  EXPECT_EQ(result.conditions[0].n, 40u);
  EXPECT_DOUBLE_EQ(result.conditions[0].proportion, 5.0 / 40.0);
  ASSERT_TRUE(threshold_of(result, "temple").level);
  EXPECT_DOUBLE_EQ(*threshold_of(result, "temple").level, 7.5);
  // Holm adjusts within the group: adjusted >= raw, monotone in the raw order.
  for (const ConditionRow& row : result.conditions) EXPECT_GE(row.p_holm, row.p_value);
}

TEST(StudyAnalysis, AGapAboveTheThresholdIsNotSkipped) {
  // 10 is distinguished again: the threshold must not be 5 even though 5 passes.
  StudyData data = study("2afc", "same", {5, 7.5, 10, 12.5});
  ParticipantData participant;
  participant.participant = "P001";
  add_comparisons(participant, "2afc-same", "s", 5, 40, 30);
  add_comparisons(participant, "2afc-same", "s", 7.5, 40, 30);
  add_comparisons(participant, "2afc-same", "s", 10, 40, 4);
  add_comparisons(participant, "2afc-same", "s", 12.5, 40, 30);
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_TRUE(threshold_of(result, "s").level);
  EXPECT_DOUBLE_EQ(*threshold_of(result, "s").level, 12.5);
}

TEST(StudyAnalysis, LowerIsBetterLevelsWalkTheOtherWay) {
  // sigma of Ye et al. 2022: larger is more compressed (worse).
  StudyData data = study("2afc", "same", {1.4, 2.0, 2.6}, /*higher_is_better=*/false);
  ParticipantData participant;
  participant.participant = "P001";
  add_comparisons(participant, "2afc-same", "s", 1.4, 40, 30);
  add_comparisons(participant, "2afc-same", "s", 2.0, 40, 25);
  add_comparisons(participant, "2afc-same", "s", 2.6, 40, 3);
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_TRUE(threshold_of(result, "s").level);
  EXPECT_DOUBLE_EQ(*threshold_of(result, "s").level, 2.0);
}

TEST(StudyAnalysis, TooFewTrialsForAnyLevelToBeDistinguishedGiveNoThreshold) {
  // Issue 18: 2 participants x 2 repeats = 4 trials a level over 5 levels. Even 0 of 4 "same" has a
  // two-sided p of 0.125, Holm-adjusted 0.625: no level can be distinguished, so "threshold 4"
  // would only say that the study was too small. No threshold, and the note says why.
  StudyData data = study("2afc", "same", {4, 8, 16, 32, 64});
  ParticipantData participant;
  participant.participant = "P001";
  for (double level : {4.0, 8.0, 16.0, 32.0, 64.0})
    add_comparisons(participant, "2afc-same", "s", level, 4, level < 20 ? 0 : 3);
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());
  const GroupThreshold& threshold = threshold_of(result, "s");
  EXPECT_FALSE(threshold.level);
  EXPECT_TRUE(threshold.unsupported);
  EXPECT_NE(threshold.note.find("too few trials"), std::string::npos) << threshold.note;
  EXPECT_NE(threshold.note.find("0.625"), std::string::npos) << threshold.note;
  // One more trial a level is still too few (5 x 2 x 0.5^5 = 0.3125); with 7 (5 x 0.0156 = 0.078)
  // still; with 8 (5 x 0.0078 = 0.039) a level can be distinguished and the walk runs.
  for (const auto& [trials, supported] : {std::pair{5, false}, std::pair{7, false}, std::pair{8, true}}) {
    StudyData more = study("2afc", "same", {4, 8, 16, 32, 64});
    ParticipantData p;
    p.participant = "P001";
    for (double level : {4.0, 8.0, 16.0, 32.0, 64.0})
      add_comparisons(p, "2afc-same", "s", level, trials, level < 20 ? 0 : trials);
    more.participants.push_back(p);
    const GroupThreshold& t = threshold_of(analyse_study(more, quick_options()), "s");
    SCOPED_TRACE(trials);
    EXPECT_EQ(t.unsupported, !supported);
    EXPECT_EQ(t.level.has_value(), supported);
    if (supported) {
      EXPECT_DOUBLE_EQ(*t.level, 32.0);
    }
  }
}

// 10 trials a level at 4, 8, ..., 64, answered "same" 0, 1, 2, 3 and 8 times: only level 4 is
// distinguished after Holm, while the answers cross half-way near 40.
StudyData one_in_ten_at_eight() {
  StudyData data = study("2afc", "same", {4, 8, 16, 32, 64});
  ParticipantData participant;
  participant.participant = "P001";
  const std::map<double, int> same = {{4, 0}, {8, 1}, {16, 2}, {32, 3}, {64, 8}};
  for (const auto& [level, k] : same) add_comparisons(participant, "2afc-same", "s", level, 10, k);
  data.participants.push_back(participant);
  return data;
}

TEST(StudyAnalysis, StarsFollowTheHolmAdjustedPAndHolmOnlyPassesAreNamed) {
  // 1 of 10 "same" at 8: raw p 0.021 (*), Holm 0.086 (no star): the threshold walk passes it, and
  // the note says that only Holm's correction let it pass.
  const AnalysisResult result = analyse_study(one_in_ten_at_eight(), quick_options());
  for (const ConditionRow& row : result.conditions) {
    SCOPED_TRACE(row.condition);
    EXPECT_EQ(row.stars, significance_stars(row.p_holm));
  }
  ASSERT_EQ(result.conditions.size(), 5u);
  EXPECT_EQ(result.conditions[1].stars, "");    // level 8: p 0.021 unadjusted, 0.086 adjusted
  EXPECT_EQ(result.conditions[0].stars, "**");  // level 4: Holm 0.0098
  const GroupThreshold& threshold = threshold_of(result, "s");
  ASSERT_TRUE(threshold.level);
  EXPECT_DOUBLE_EQ(*threshold.level, 8.0);
  EXPECT_FALSE(threshold.unsupported);
  EXPECT_NE(threshold.note.find("level 8 passes only after Holm's correction (1 of 10"), std::string::npos)
      << threshold.note;
}

TEST(StudyAnalysis, AThresholdTheFitExcludesIsNamedWithTheFit) {
  // The answers cross half-way near 40 while the tests, with 10 trials a level, only distinguish
  // level 4: the walk says 8, the fit's interval lies far above it, and the note gives both.
  const AnalysisResult result = analyse_study(one_in_ten_at_eight(), quick_options());
  const GroupThreshold& threshold = threshold_of(result, "s");
  ASSERT_FALSE(result.fits.empty());
  ASSERT_FALSE(result.fits.front().fits.empty());
  const PsychometricFit& fit = result.fits.front().fits.front();
  EXPECT_GT(fit.threshold_interval.lower, 8.0);
  EXPECT_NE(threshold.note.find("fit's threshold is"), std::string::npos) << threshold.note;
  EXPECT_NE(threshold.note.find("outside the walk's bracket (8 to the next more degraded level): less degraded"),
            std::string::npos)
      << threshold.note;
  // Where the fit agrees (a clear step between 16 and 32 with 40 trials a level), no such note.
  StudyData clear = study("2afc", "same", {4, 8, 16, 32, 64});
  ParticipantData p;
  p.participant = "P001";
  const std::map<double, int> clear_same = {{4, 2}, {8, 4}, {16, 14}, {32, 30}, {64, 36}};
  for (const auto& [level, k] : clear_same) add_comparisons(p, "2afc-same", "s", level, 40, k);
  clear.participants.push_back(p);
  const GroupThreshold& agreed = threshold_of(analyse_study(clear, quick_options()), "s");
  EXPECT_EQ(agreed.note.find("fit's threshold is"), std::string::npos) << agreed.note;
}

TEST(StudyAnalysis, PreferenceCountsVotesForTheTestStimulus) {
  // Ye et al. 2022 Table 2: 49 of 72 for the test; one-sided (greater) p = 0.00147 -> "**".
  StudyData data = study("2afc", "better", {1.0});
  ParticipantData participant;
  participant.participant = "P001";
  add_comparisons(participant, "2afc-better", "s", 1.0, 72, 49);
  data.participants.push_back(participant);
  AnalysisOptions options = quick_options();
  options.alternative = Alternative::greater;
  const AnalysisResult result = analyse_study(data, options);
  ASSERT_EQ(result.conditions.size(), 1u);
  EXPECT_EQ(result.conditions[0].k, 49u);
  EXPECT_EQ(result.conditions[0].stars, "**");
  EXPECT_NEAR(result.conditions[0].p_value, 0.001471380265062488, 1e-12);
  EXPECT_DOUBLE_EQ(result.guess_rate, 0.5);
}

TEST(StudyAnalysis, RatingThresholdIsTheMostDegradedLevelWithMeanAtLeastTwo) {
  StudyData data = study("rating", "", {1.4, 2.0, 2.6, 2.8}, /*higher_is_better=*/false);
  ParticipantData participant;
  participant.participant = "P001";
  // Scores 3 or 1: mean = 1 + 2 * share of 3s. 2.6: 10 of 20 -> mean 2.0 exactly (kept); 2.8: 9 of 20.
  add_comparisons(participant, "rating", "s", 1.4, 20, 18);
  add_comparisons(participant, "rating", "s", 2.0, 20, 15);
  add_comparisons(participant, "rating", "s", 2.6, 20, 10);
  add_comparisons(participant, "rating", "s", 2.8, 20, 9);
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_TRUE(threshold_of(result, "s").level);
  EXPECT_DOUBLE_EQ(*threshold_of(result, "s").level, 2.6);
  for (const ConditionRow& row : result.conditions) ASSERT_TRUE(row.mean_rating);
  EXPECT_DOUBLE_EQ(*result.conditions[2].mean_rating, 2.0);
}

TEST(StudyAnalysis, PairThresholdPerParticipantThenMeanAndSd) {
  StudyData data = study("pair", "", {5, 10, 15, 20});
  // P1 judges 10 and above as good as the reference (>= half), P2 from 20, P3 from 5.
  const std::vector<std::pair<std::string, std::vector<int>>> favour_per_level = {
      {"P001", {1, 3, 6, 6}}, {"P002", {0, 1, 2, 4}}, {"P003", {3, 4, 5, 6}}};
  for (const auto& [name, favour] : favour_per_level) {
    ParticipantData participant;
    participant.participant = name;
    for (size_t i = 0; i < favour.size(); ++i)
      add_comparisons(participant, "pair", "sponza", data.levels[i], 6, favour[i]);
    data.participants.push_back(participant);
  }
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_EQ(result.participants.size(), 3u);
  const double expected[] = {10, 20, 5};
  for (size_t i = 0; i < 3; ++i) {
    ASSERT_EQ(result.participants[i].thresholds.size(), 1u);
    ASSERT_TRUE(result.participants[i].thresholds[0].level);
    EXPECT_DOUBLE_EQ(*result.participants[i].thresholds[0].level, expected[i]);
  }
  const GroupThreshold* summary = nullptr;
  for (const GroupThreshold& threshold : result.thresholds)
    if (threshold.mean) summary = &threshold;
  ASSERT_NE(summary, nullptr);
  EXPECT_DOUBLE_EQ(*summary->mean, 35.0 / 3.0);
  EXPECT_NEAR(*summary->sd, 7.637626158259733, 1e-12);  // sample SD of {10, 20, 5}
  EXPECT_EQ(summary->participants_with_threshold, 3);
}

StudyTrial ramp_trial(bool toward_reference, std::vector<std::string> answers) {
  StudyTrial trial;
  trial.scene = "sponza";
  trial.condition = toward_reference ? "ramp_up" : "ramp_down";
  trial.ramp_toward_reference = toward_reference;
  trial.sequence_levels = {5.0, 10.0, 15.0, 20.0, std::nullopt};  // worst .. best, then the reference
  if (!toward_reference) std::reverse(trial.sequence_levels.begin(), trial.sequence_levels.end());
  trial.answers = std::move(answers);
  for (size_t i = 0; i < trial.answers.size(); ++i) trial.answer_steps.push_back(static_cast<int>(i) + 1);
  return trial;
}

TEST(StudyAnalysis, RampThresholdIsTheMostDegradedWronglyAnsweredStepAveragedOverRamps) {
  StudyData data = study("ramp", "", {5, 10, 15, 20});
  ParticipantData participant;
  participant.participant = "P001";
  // Up: steps 5->10, 10->15, 15->20, 20->ref; the 10->15 and 15->20 steps missed: threshold 10.
  participant.trials.push_back(ramp_trial(true, {"increased", "same", "same", "increased"}));
  // Down: ref->20, 20->15, 15->10, 10->5; only 20->15 answered wrongly: threshold 15.
  participant.trials.push_back(ramp_trial(false, {"decreased", "increased", "decreased", "decreased"}));
  // Every step right: censored at the best level, 20.
  participant.trials.push_back(ramp_trial(true, {"increased", "increased", "increased", "increased"}));
  // A step left unanswered (a timeout, ""): not counted, though its answered steps are all right.
  participant.trials.push_back(ramp_trial(true, {"increased", "", "increased", "increased"}));
  // A step never answered at all (no response event for step 4): not counted either.
  participant.trials.push_back(ramp_trial(false, {"decreased", "decreased", "decreased"}));
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_EQ(result.participants[0].thresholds.size(), 1u);
  ASSERT_TRUE(result.participants[0].thresholds[0].level);
  EXPECT_DOUBLE_EQ(*result.participants[0].thresholds[0].level, (10.0 + 15.0 + 20.0) / 3.0);
  const std::string& note = result.participants[0].thresholds[0].note;
  EXPECT_NE(note.find("1 of 5 ramps had every step right"), std::string::npos) << note;
  EXPECT_NE(note.find("2 of 5 ramps had a step left unanswered"), std::string::npos) << note;
}

TEST(StudyAnalysis, SliderThresholdIsTheMeanSavedLevel) {
  StudyData data = study("slider", "", {5, 10, 15, 20});
  for (const auto& [name, saved] :
       std::vector<std::pair<std::string, std::vector<double>>>{{"P1", {5, 10, 30}}, {"P2", {20}}}) {
    ParticipantData participant;
    participant.participant = name;
    for (double level : saved) {
      StudyTrial trial;
      trial.scene = "sponza";
      trial.condition = "slider";
      trial.answers = {"reference", "up", "save"};
      trial.answer_steps = {0, 1, 2};
      trial.saved_level = level;
      participant.trials.push_back(trial);
    }
    data.participants.push_back(participant);
  }
  const AnalysisResult result = analyse_study(data, quick_options());
  EXPECT_DOUBLE_EQ(*result.participants[0].thresholds[0].level, 15.0);  // the mean, not the median (10)
  EXPECT_DOUBLE_EQ(*result.participants[1].thresholds[0].level, 20.0);
  ASSERT_EQ(result.thresholds.size(), 1u);
  EXPECT_DOUBLE_EQ(*result.thresholds[0].mean, 17.5);
  EXPECT_DOUBLE_EQ(*result.thresholds[0].sd, 3.5355339059327378);  // sample SD (n - 1) of {15, 20}
}

TEST(StudyAnalysis, ExcludedParticipantsAndEmptyConditionsAreListedAsLeftOut) {
  StudyData data = study("2afc", "same", {5, 10, 15});
  ParticipantData kept, excluded;
  kept.participant = "P001";
  add_comparisons(kept, "2afc-same", "s", 5, 10, 2);
  add_comparisons(kept, "2afc-same", "s", 10, 10, 8);
  excluded.participant = "P002";
  excluded.excluded = true;
  excluded.attention_errors = 3;
  add_comparisons(excluded, "2afc-same", "s", 15, 10, 0);
  data.participants = {kept, excluded};
  const AnalysisResult result = analyse_study(data, quick_options());
  EXPECT_EQ(result.conditions.size(), 2u);  // level 15 only had the excluded participant's trials
  bool excluded_listed = false, empty_listed = false;
  for (const LeftOut& item : result.left_out) {
    excluded_listed |= item.what == "participant P002";
    empty_listed |= item.what.find("foveal_deg=15") != std::string::npos;
  }
  EXPECT_TRUE(excluded_listed);
  EXPECT_TRUE(empty_listed);
}

TEST(StudyAnalysis, ScenesArePooledAsAllWhenThereAreSeveral) {
  StudyData data = study("2afc", "same", {5});
  ParticipantData participant;
  participant.participant = "P001";
  add_comparisons(participant, "2afc-same", "a", 5, 10, 4);
  add_comparisons(participant, "2afc-same", "b", 5, 30, 6);
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_EQ(result.conditions.size(), 3u);
  const ConditionRow* all = nullptr;
  for (const ConditionRow& row : result.conditions)
    if (row.group.scene == "all") all = &row;
  ASSERT_NE(all, nullptr);
  EXPECT_EQ(all->n, 40u);
  EXPECT_EQ(all->k, 10u);
}

// The headline (docs/analysis.md, "The headline"): a degenerate fit is not estimable with its
// reason and no number, and [analysis] headline = "paper" puts the paper's rule in its place.
TEST(StudyAnalysisHeadline, AFitWhoseThresholdLeavesTheLevelsIsNotEstimable) {
  StudyData data = study("2afc", "same", {4, 8, 16, 32, 64});
  ParticipantData participant;
  participant.participant = "P001";
  for (double level : {4.0, 8.0, 16.0, 32.0, 64.0}) add_comparisons(participant, "2afc-same", "temple", level, 20, 0);
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_EQ(result.headlines.size(), 1u);
  const Headline& headline = result.headlines.front();
  EXPECT_EQ(headline.status, HeadlineStatus::not_estimable);
  EXPECT_FALSE(headline.value);
  EXPECT_FALSE(headline.lower);
  EXPECT_FALSE(headline.reason.empty());
}

TEST(StudyAnalysisHeadline, TheFitIsTheHeadlineAndTheWalkStaysBesideItOrTakesItsPlaceWhenTheConfigSaysSo) {
  StudyData data = study("2afc", "same", {2.5, 5, 7.5, 10});
  ParticipantData participant;
  participant.participant = "P001";
  add_comparisons(participant, "2afc-same", "temple", 2.5, 40, 3);
  add_comparisons(participant, "2afc-same", "temple", 5, 40, 12);
  add_comparisons(participant, "2afc-same", "temple", 7.5, 40, 30);
  add_comparisons(participant, "2afc-same", "temple", 10, 40, 37);
  data.participants.push_back(participant);
  const AnalysisResult estimate = analyse_study(data, quick_options());
  ASSERT_EQ(estimate.headlines.size(), 1u);
  const Headline& fit = estimate.headlines.front();
  EXPECT_EQ(fit.status, HeadlineStatus::estimated) << fit.reason;
  ASSERT_TRUE(fit.value && fit.lower && fit.upper);
  EXPECT_GT(*fit.value, 5.0);
  EXPECT_LT(*fit.value, 7.5);
  EXPECT_NE(fit.method.find("logistic fit"), std::string::npos);
  EXPECT_EQ(fit.paper_rule, "Polychronakis et al. 2023, 4.4 and 5.1");
  ASSERT_TRUE(fit.paper_value);
  EXPECT_DOUBLE_EQ(*fit.paper_value, 7.5);
  EXPECT_FALSE(fit.paper_rule_is_headline);

  data.config.analysis.headline_is_paper_rule = true;
  const AnalysisResult paper = analyse_study(data, quick_options());
  const Headline& walk = paper.headlines.front();
  EXPECT_TRUE(walk.paper_rule_is_headline);
  ASSERT_TRUE(walk.value);
  EXPECT_DOUBLE_EQ(*walk.value, 7.5);
  ASSERT_FALSE(walk.notes.empty());
  EXPECT_NE(walk.notes.front().find("the design's estimate"), std::string::npos) << walk.notes.front();
}

TEST(StudyAnalysisHeadline, PreferenceShareWithItsClopperPearsonInterval) {
  StudyData data = study("2afc", "better", {});
  ParticipantData participant;
  participant.participant = "P001";
  add_comparisons(participant, "2afc-better", "temple", 1.0, 20, 5);  // the test chosen 5 times: the reference 15
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_EQ(result.headlines.size(), 1u);
  const Headline& share = result.headlines.front();
  EXPECT_EQ(share.quantity, "preference share");
  ASSERT_TRUE(share.value && share.lower && share.upper);
  EXPECT_DOUBLE_EQ(*share.value, 0.75);
  const ProportionInterval interval = clopper_pearson_interval(15, 20, 0.95);
  EXPECT_DOUBLE_EQ(*share.lower, interval.lower);
  EXPECT_DOUBLE_EQ(*share.upper, interval.upper);
}

}  // namespace
}  // namespace fovlab::analysis
