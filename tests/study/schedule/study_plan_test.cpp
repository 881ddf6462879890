// Tests of study/schedule/study_plan.h: the expanded schedule of a session as a pure function of
// (config, participant): trial counts per protocol, counterbalancing, ramps, sliders, block order,
// stimulus deduplication and participant IDs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "protocols/stimuli/stimulus_settings.h"
#include "core/input_error.h"
#include "core/prng.h"
#include "study/config/study_config.h"
#include "study/schedule/study_plan.h"

namespace fovlab {
namespace {

struct Sections {
  std::string stimulus_extra;  // appended to [stimulus] (variants)
  std::string test = "[stimulus.test]\nmethod = \"gt\"\n";
  std::string levels = "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16, 32, 64]\n";
  std::string protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 2\n";
  std::string timing = "[timing]\nblack_interval_s = 0.25\ninter_trial_s = 0.75\n";
  std::string attention = "[attention]\nshare = 0.2\n";
  std::string blocks = "[[block]]\nscene = \"primitives\"\n\n[[block]]\nscene = \"columns\"\n";
};

StudyConfig make_config(const Sections& s) {
  std::string text = R"([study]
name = "plan_test"
seed = 99

[display]
width_px = 64
height_px = 48
refresh_hz = 60
width_mm = 400
height_mm = 300
viewing_distance_mm = 600

[stimulus]
duration_s = 0.5
frames_per_second = 10
camera_start_s = 1.0

[stimulus.reference]
method = "gt"

)";
  text += s.test + "\n" + s.stimulus_extra + "\n" + s.levels + "\n" + s.protocol + "\n" + s.timing + "\n" +
          s.attention + "\n" + s.blocks;
  return parse_study_config_text(text, "plan_test.toml", renderer_scene_catalog());
}

const std::string kVariants = R"(
[[stimulus.variant]]
name = "coarse"
hit_threshold = 1.0

[[stimulus.variant]]
name = "fine"
hit_threshold = 0.1
)";

// Everything of a trial, as text, to compare plans.
std::string describe(const Trial& t) {
  std::ostringstream out;
  out << t.index << "|" << t.block << "|" << t.condition << "|" << t.variant << "|"
      << (t.level ? std::to_string(*t.level) : "-") << "|" << t.attention_check << t.reference_first
      << t.ramp_toward_reference << "|" << t.reference << "|" << t.slider_start << "|";
  for (int id : t.sequence) out << id << ",";
  return out.str();
}

std::vector<std::string> describe(const StudyPlan& plan) {
  std::vector<std::string> lines;
  for (const Trial& trial : plan.trials) lines.push_back(describe(trial));
  for (const PlannedStimulus& s : plan.stimuli)
    lines.push_back(s.spec.canonical() + "|" + std::to_string(s.is_reference) + "|" + s.variant + "|" +
                    (s.level ? std::to_string(*s.level) : "-"));
  for (const PlannedBlock& b : plan.blocks)
    lines.push_back(b.name + "|" + b.scene + "|" + std::to_string(b.first_trial) + "|" + std::to_string(b.trial_count));
  return lines;
}

// Invariants every plan must satisfy.
void check_structure(const StudyPlan& plan) {
  int expected_first = 0;
  for (size_t b = 0; b < plan.blocks.size(); ++b) {
    EXPECT_EQ(plan.blocks[b].first_trial, expected_first) << "block " << b;
    expected_first += plan.blocks[b].trial_count;
  }
  EXPECT_EQ(expected_first, static_cast<int>(plan.trials.size()));
  for (size_t i = 0; i < plan.trials.size(); ++i) {
    const Trial& trial = plan.trials[i];
    EXPECT_EQ(trial.index, static_cast<int>(i));
    ASSERT_GE(trial.block, 0);
    ASSERT_LT(trial.block, static_cast<int>(plan.blocks.size()));
    const PlannedBlock& block = plan.blocks[static_cast<size_t>(trial.block)];
    EXPECT_GE(trial.index, block.first_trial);
    EXPECT_LT(trial.index, block.first_trial + block.trial_count);
    ASSERT_GE(trial.reference, 0);
    ASSERT_LT(trial.reference, static_cast<int>(plan.stimuli.size()));
    const PlannedStimulus& reference = plan.stimuli[static_cast<size_t>(trial.reference)];
    EXPECT_TRUE(reference.is_reference);
    EXPECT_EQ(reference.spec.scene, block.scene);
    for (int id : trial.sequence) {
      ASSERT_GE(id, 0);
      ASSERT_LT(id, static_cast<int>(plan.stimuli.size()));
      EXPECT_EQ(plan.stimuli[static_cast<size_t>(id)].spec.scene, block.scene);
    }
  }
}

std::optional<double> level_of(const StudyPlan& plan, int id) {
  const PlannedStimulus& s = plan.stimuli.at(static_cast<size_t>(id));
  return s.is_reference ? std::nullopt : s.level;
}

// --- determinism ------------------------------------------------------------------------------------

TEST(ProtocolsSchedule, SameConfigAndParticipantGiveTheSamePlan) {
  const StudyConfig config = make_config(Sections{});
  const StudyPlan a = make_study_plan(config, "p01");
  const StudyPlan b = make_study_plan(config, "p01");
  EXPECT_EQ(describe(a), describe(b));
  EXPECT_EQ(a.participant, "p01");
  EXPECT_EQ(a.session_seed, session_seed(config.seed, "p01"));
  EXPECT_EQ(a.config.hash, config.hash);
  // Parsing the same text again gives the same plan too (nothing depends on addresses or time).
  const StudyPlan c = make_study_plan(make_config(Sections{}), "p01");
  EXPECT_EQ(describe(a), describe(c));
  check_structure(a);
}

TEST(ProtocolsSchedule, DifferentParticipantsGetDifferentOrders) {
  const StudyConfig config = make_config(Sections{});
  const StudyPlan a = make_study_plan(config, "p01");
  const StudyPlan b = make_study_plan(config, "p02");
  EXPECT_NE(a.session_seed, b.session_seed);
  EXPECT_NE(session_seed(config.seed, "p01"), session_seed(config.seed + 1, "p01"));
  ASSERT_EQ(a.trials.size(), b.trials.size());
  std::vector<std::string> order_a, order_b;
  for (size_t i = 0; i < a.trials.size(); ++i) {
    order_a.push_back(a.trials[i].condition + (a.trials[i].reference_first ? "+" : "-"));
    order_b.push_back(b.trials[i].condition + (b.trials[i].reference_first ? "+" : "-"));
  }
  EXPECT_NE(order_a, order_b);
  // Same multiset of trials, only the order differs.
  std::sort(order_a.begin(), order_a.end());
  std::sort(order_b.begin(), order_b.end());
  EXPECT_EQ(order_a, order_b);
  // The stimuli do not depend on the participant.
  ASSERT_EQ(a.stimuli.size(), b.stimuli.size());
  for (size_t i = 0; i < a.stimuli.size(); ++i) EXPECT_EQ(a.stimuli[i].spec.canonical(), b.stimuli[i].spec.canonical());
}

// --- 2afc counts and conditions --------------------------------------------------------------------

TEST(ProtocolsSchedule, TwoAfcCountsLevelsTimesVariantsTimesRepeatsPlusChecks) {
  Sections s;
  s.stimulus_extra = kVariants;
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  check_structure(plan);
  ASSERT_EQ(plan.blocks.size(), 2u);
  // 5 levels x 2 variants x 2 repeats = 20 comparisons; share 0.2 of all trials: 5 checks (5 / 25).
  for (const PlannedBlock& block : plan.blocks) EXPECT_EQ(block.trial_count, 25);
  EXPECT_EQ(plan.trials.size(), 50u);
  std::map<std::pair<int, std::string>, int> per_condition;
  int checks = 0;
  for (const Trial& trial : plan.trials) {
    if (trial.attention_check) {
      ++checks;
      EXPECT_EQ(trial.condition, "attention_check");
      EXPECT_FALSE(trial.level.has_value());
      EXPECT_EQ(trial.sequence, (std::vector<int>{trial.reference, trial.reference}));
      continue;
    }
    ++per_condition[{trial.block, trial.condition}];
    ASSERT_TRUE(trial.level.has_value());
    ASSERT_EQ(trial.sequence.size(), 2u);
    // The condition names the variant and the level.
    std::ostringstream name;
    name << trial.variant << "/level=" << *trial.level;
    EXPECT_EQ(trial.condition, name.str());
    const int test = trial.sequence[0] == trial.reference ? trial.sequence[1] : trial.sequence[0];
    EXPECT_NE(test, trial.reference);
    EXPECT_EQ(level_of(plan, test), trial.level);
    EXPECT_EQ(plan.stimuli[static_cast<size_t>(test)].variant, trial.variant);
  }
  EXPECT_EQ(checks, 10);
  EXPECT_EQ(per_condition.size(), 20u);  // 2 blocks x 10 conditions
  for (const auto& [condition, count] : per_condition) EXPECT_EQ(count, 2) << condition.second;
  EXPECT_EQ(per_condition.count({0, "coarse/level=4"}), 1u);
  EXPECT_EQ(per_condition.count({1, "fine/level=64"}), 1u);
}

// A config of a few kilobytes can ask for billions of trials (the readers plan the config a log
// carries, so a forged log could too); such a plan is refused before a trial is made, in one line.
TEST(ProtocolsSchedule, APlanPastWhatALogCouldHoldIsRefusedBeforeItIsMade) {
  Sections s;
  std::string values;
  for (int level = 1; level <= 3000; ++level) values += (level > 1 ? ", " : "") + std::to_string(level);
  s.levels = "[levels]\nparameter = \"max_steps\"\nvalues = [" + values + "]\n";
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 1000\n";
  const StudyConfig huge = make_config(s);  // 2 blocks x 3000 levels x 1000 repeats, plus checks
  try {
    make_study_plan(huge, "p01");
    FAIL() << "a plan of 7.5 million trials was made";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("plan_test.toml: more than 4000000 trials planned a participant", 0), 0u)
        << error.what();
  }
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 100\n";  // 750,000 trials: made
  EXPECT_EQ(make_study_plan(make_config(s), "p01").trials.size(), 750000u);
}

TEST(ProtocolsSchedule, AttentionCheckShareIsOfAllTrialsRounded) {
  struct Case {
    const char* share;
    const char* values;
    int repeats;
    int expected_checks;
  };
  // checks = round(share / (1 - share) * comparisons): then checks / (checks + comparisons) ~ share.
  const std::vector<Case> cases = {
      {"0", "[4, 8, 16, 32, 64]", 2, 0}, {"0.2", "[4, 8, 16, 32, 64]", 2, 3},  // 2.5 -> 3 (13 trials)
      {"0.5", "[4, 8, 16]", 2, 6},       {"0.1", "[4, 8, 16, 32, 64]", 2, 1},  // 1.11 -> 1
      {"0.25", "[4, 8, 16, 32]", 4, 5},  {"0.9", "[4]", 2, 18},
  };
  for (const Case& c : cases) {
    Sections s;
    s.attention = std::string("[attention]\nshare = ") + c.share + "\n";
    s.levels = std::string("[levels]\nparameter = \"max_steps\"\nvalues = ") + c.values + "\n";
    s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = " + std::to_string(c.repeats) + "\n";
    s.blocks = "[[block]]\nscene = \"primitives\"\n";
    const StudyConfig config = make_config(s);
    const StudyPlan plan = make_study_plan(config, "p01");
    const int comparisons = static_cast<int>(config.levels.values.size()) * c.repeats;
    int checks = 0;
    for (const Trial& trial : plan.trials) checks += trial.attention_check;
    EXPECT_EQ(checks, c.expected_checks) << "share " << c.share;
    EXPECT_EQ(static_cast<int>(plan.trials.size()), comparisons + c.expected_checks) << "share " << c.share;
  }
}

TEST(ProtocolsSchedule, OneConditionWithoutLevelsOrVariants) {
  Sections s;
  s.levels.clear();
  s.attention.clear();
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 6\n";
  s.test = "[stimulus.test]\nmethod = \"ipr\"\n";
  s.blocks = "[[block]]\nscene = \"primitives\"\n";
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  check_structure(plan);
  ASSERT_EQ(plan.trials.size(), 6u);
  for (const Trial& trial : plan.trials) {
    EXPECT_EQ(trial.condition, "test");
    EXPECT_FALSE(trial.level.has_value());
    EXPECT_FALSE(trial.attention_check);
  }
  ASSERT_EQ(plan.stimuli.size(), 2u);  // GT reference, IPR test
  int references = 0;
  for (const PlannedStimulus& stimulus : plan.stimuli) references += stimulus.is_reference;
  EXPECT_EQ(references, 1);
}

TEST(ProtocolsSchedule, CounterbalanceGivesReferenceFirstInExactlyHalf) {
  Sections s;
  s.stimulus_extra = kVariants;
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 4\n";
  for (const char* participant : {"p01", "p02", "xyz"}) {
    const StudyPlan plan = make_study_plan(make_config(s), participant);
    check_structure(plan);
    std::map<std::pair<int, std::string>, std::pair<int, int>> first_and_total;
    for (const Trial& trial : plan.trials) {
      if (trial.attention_check) continue;
      auto& [first, total] = first_and_total[{trial.block, trial.condition}];
      first += trial.reference_first;
      ++total;
      ASSERT_EQ(trial.sequence.size(), 2u);
      EXPECT_EQ(trial.sequence[0] == trial.reference, trial.reference_first) << describe(trial);
      EXPECT_EQ(trial.sequence[1] == trial.reference, !trial.reference_first) << describe(trial);
    }
    EXPECT_EQ(first_and_total.size(), 20u);
    for (const auto& [condition, counts] : first_and_total) {
      EXPECT_EQ(counts.second, 4) << condition.second;
      EXPECT_EQ(counts.first, 2) << condition.second;
    }
  }
}

TEST(ProtocolsSchedule, WithoutCounterbalanceTheOrderIsRandomButConsistent) {
  Sections s;
  s.protocol = "[protocol]\nkind = \"pair\"\nrepeats = 5\ncounterbalance = false\n";
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  check_structure(plan);
  int reference_first = 0, comparisons = 0;
  for (const Trial& trial : plan.trials) {
    if (trial.attention_check) continue;
    ++comparisons;
    reference_first += trial.reference_first;
    EXPECT_EQ(trial.sequence[0] == trial.reference, trial.reference_first);
  }
  EXPECT_EQ(comparisons, 50);  // 5 levels x 5 repeats x 2 blocks
  EXPECT_GT(reference_first, 10);
  EXPECT_LT(reference_first, 40);
}

TEST(ProtocolsSchedule, FixedTrialOrderIsTheConfigOrder) {
  Sections s;
  s.stimulus_extra = kVariants;
  s.levels = "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8]\n";
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 2\ntrial_order = \"fixed\"\n";
  s.attention = "[attention]\nshare = 0.2\n";  // 8 comparisons: round(2) = 2 checks
  s.blocks = "[[block]]\nscene = \"primitives\"\n";
  const StudyPlan a = make_study_plan(make_config(s), "p01");
  const StudyPlan b = make_study_plan(make_config(s), "p02");
  check_structure(a);
  std::vector<std::string> conditions;
  std::vector<bool> first;
  for (const Trial& trial : a.trials) {
    conditions.push_back(trial.condition);
    first.push_back(trial.reference_first);
  }
  EXPECT_EQ(conditions, (std::vector<std::string>{"coarse/level=4", "coarse/level=4", "coarse/level=8",
                                                  "coarse/level=8", "fine/level=4", "fine/level=4", "fine/level=8",
                                                  "fine/level=8", "attention_check", "attention_check"}));
  EXPECT_EQ(std::vector<bool>(first.begin(), first.begin() + 8),
            (std::vector<bool>{true, false, true, false, true, false, true, false}));
  // A fixed order does not depend on the participant.
  ASSERT_EQ(a.trials.size(), b.trials.size());
  for (size_t i = 0; i < a.trials.size(); ++i) EXPECT_EQ(describe(a.trials[i]), describe(b.trials[i]));
}

// --- ramp and slider --------------------------------------------------------------------------------

void check_ramp(bool higher_is_better) {
  Sections s;
  s.attention.clear();
  s.levels = std::string("[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16, 32]\nhigher_is_better = ") +
             (higher_is_better ? "true" : "false") + "\n";
  s.protocol = "[protocol]\nkind = \"ramp\"\nrepeats = 3\ntrial_order = \"fixed\"\n";
  s.stimulus_extra = kVariants;
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  check_structure(plan);
  // 2 variants x 3 repeats x 2 directions per block.
  for (const PlannedBlock& block : plan.blocks) EXPECT_EQ(block.trial_count, 12);
  ASSERT_EQ(plan.trials.size(), 24u);
  // The ladder runs from the level least like the reference to the one most like it.
  const std::vector<std::optional<double>> ladder = higher_is_better
                                                        ? std::vector<std::optional<double>>{4.0, 8.0, 16.0, 32.0}
                                                        : std::vector<std::optional<double>>{32.0, 16.0, 8.0, 4.0};
  std::vector<std::optional<double>> up = ladder;
  up.push_back(std::nullopt);  // the reference last
  std::vector<std::optional<double>> down(up.rbegin(), up.rend());
  std::map<std::string, int> per_direction;
  for (const Trial& trial : plan.trials) {
    EXPECT_FALSE(trial.attention_check);
    EXPECT_FALSE(trial.level.has_value());
    std::vector<std::optional<double>> levels;
    for (int id : trial.sequence) {
      levels.push_back(level_of(plan, id));
      if (!level_of(plan, id)) {
        EXPECT_EQ(id, trial.reference);
      }
      EXPECT_EQ(plan.stimuli[static_cast<size_t>(id)].variant,
                plan.stimuli[static_cast<size_t>(id)].is_reference ? "" : trial.variant);
    }
    const std::string direction = trial.ramp_toward_reference ? "up" : "down";
    EXPECT_EQ(levels, trial.ramp_toward_reference ? up : down) << describe(trial);
    const std::string suffix = trial.ramp_toward_reference ? "ramp_up" : "ramp_down";
    EXPECT_TRUE(trial.condition.size() >= suffix.size() &&
                trial.condition.compare(trial.condition.size() - suffix.size(), suffix.size(), suffix) == 0)
        << trial.condition;
    EXPECT_NE(trial.condition.find(trial.variant), std::string::npos) << trial.condition;
    ++per_direction[std::to_string(trial.block) + trial.variant + direction];
  }
  EXPECT_EQ(per_direction.size(), 8u);  // 2 blocks x 2 variants x 2 directions
  for (const auto& [key, count] : per_direction) EXPECT_EQ(count, 3) << key;
}

TEST(ProtocolsSchedule, RampHigherIsBetter) { check_ramp(true); }
TEST(ProtocolsSchedule, RampLowerIsBetter) { check_ramp(false); }

TEST(ProtocolsSchedule, RampExpectedDuration) {
  Sections s;
  s.attention.clear();
  s.levels = "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16, 32]\n";
  s.protocol = "[protocol]\nkind = \"ramp\"\nrepeats = 1\n";
  s.timing = "[timing]\nblack_interval_s = 0.25\ninter_trial_s = 0.75\nrest_between_blocks_s = 10\n";
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  // 2 blocks x 2 trials; each: 5 stimuli of 0.5 s, 4 black intervals, 4 answers, one inter-trial.
  const double per_trial = 5 * 0.5 + 4 * 0.25 + 4 * 1.5 + 0.75;
  EXPECT_NEAR(plan.expected_duration_s(1.5), 4 * per_trial + 10.0, 1e-9);
}

TEST(ProtocolsSchedule, TwoAfcExpectedDuration) {
  Sections s;
  s.attention.clear();
  s.levels = "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8]\n";
  s.timing = "[timing]\nblack_interval_s = 0.25\ninter_trial_s = 0.75\nrest_between_blocks_s = 10\n";
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  ASSERT_EQ(plan.trials.size(), 8u);
  // Each trial: 2 x 0.5 s stimuli, one black interval, one answer (2 s), one inter-trial; one rest.
  EXPECT_NEAR(plan.expected_duration_s(2.0), 8 * (1.0 + 0.25 + 2.0 + 0.75) + 10.0, 1e-9);
}

void check_slider(bool higher_is_better, const std::string& start_line, double start_level) {
  Sections s;
  s.attention.clear();
  s.levels = std::string("[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16, 32]\nhigher_is_better = ") +
             (higher_is_better ? "true" : "false") + "\n";
  s.protocol = "[protocol]\nkind = \"slider\"\nrepeats = 2\n" + start_line;
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  check_structure(plan);
  ASSERT_EQ(plan.trials.size(), 4u);  // 2 repeats x 2 blocks
  for (const Trial& trial : plan.trials) {
    ASSERT_EQ(trial.sequence.size(), 4u);  // the ladder, no reference
    std::vector<std::optional<double>> levels;
    for (int id : trial.sequence) levels.push_back(level_of(plan, id));
    EXPECT_EQ(levels, higher_is_better ? (std::vector<std::optional<double>>{4.0, 8.0, 16.0, 32.0})
                                       : (std::vector<std::optional<double>>{32.0, 16.0, 8.0, 4.0}));
    ASSERT_GE(trial.slider_start, 0);
    ASSERT_LT(trial.slider_start, 4);
    EXPECT_EQ(level_of(plan, trial.sequence[static_cast<size_t>(trial.slider_start)]), start_level)
        << "slider_start " << trial.slider_start;
    EXPECT_FALSE(trial.attention_check);
  }
}

TEST(ProtocolsSchedule, SliderStartsAtTheConfiguredLevel) {
  check_slider(true, "start_level = 16\n", 16.0);
  check_slider(false, "start_level = 16\n", 16.0);
  check_slider(true, "", 4.0);  // default: the first level value
  check_slider(false, "", 4.0);
  check_slider(false, "start_level = 32\n", 32.0);
}

TEST(ProtocolsSchedule, SliderStartIndexValues) {
  Sections s;
  s.attention.clear();
  s.levels = "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16, 32]\nhigher_is_better = false\n";
  s.protocol = "[protocol]\nkind = \"slider\"\nstart_level = 8\n";
  EXPECT_EQ(make_study_plan(make_config(s), "p01").trials.at(0).slider_start, 2);  // ladder 32, 16, 8, 4
  s.levels = "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16, 32]\nhigher_is_better = true\n";
  EXPECT_EQ(make_study_plan(make_config(s), "p01").trials.at(0).slider_start, 1);  // ladder 4, 8, 16, 32
}

// --- blocks -----------------------------------------------------------------------------------------

const std::string kThreeBlocks =
    "[[block]]\nscene = \"primitives\"\n\n[[block]]\nscene = \"columns\"\n\n[[block]]\nscene = \"temple\"\n";

TEST(ProtocolsSchedule, FixedBlockOrderIsTheConfigOrder) {
  Sections s;
  s.blocks = kThreeBlocks;
  for (const char* participant : {"p01", "p02", "p03", "p04"}) {
    const StudyPlan plan = make_study_plan(make_config(s), participant);
    check_structure(plan);
    ASSERT_EQ(plan.blocks.size(), 3u);
    EXPECT_EQ(plan.blocks[0].name, "primitives");
    EXPECT_EQ(plan.blocks[1].name, "columns");
    EXPECT_EQ(plan.blocks[2].name, "temple");
    EXPECT_EQ(plan.blocks[2].scene, "temple");
    for (const PlannedBlock& block : plan.blocks) EXPECT_EQ(block.trial_count, 13);
  }
}

TEST(ProtocolsSchedule, RandomBlockOrderIsAPermutationPerParticipant) {
  Sections s;
  s.blocks = kThreeBlocks;
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 2\nblock_order = \"random\"\n";
  const StudyConfig config = make_config(s);
  std::set<std::vector<std::string>> orders;
  for (int p = 0; p < 30; ++p) {
    // append, not +: GCC 12's -O2 warns falsely (-Wrestrict) on "p" + std::to_string(p).
    std::string participant = "p";
    participant.append(std::to_string(p));
    const StudyPlan plan = make_study_plan(config, participant);
    check_structure(plan);
    std::vector<std::string> order;
    for (const PlannedBlock& block : plan.blocks) order.push_back(block.name);
    std::vector<std::string> sorted = order;
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(sorted, (std::vector<std::string>{"columns", "primitives", "temple"}));
    orders.insert(order);
    // The same participant gets the same order again.
    const StudyPlan again = make_study_plan(config, participant);
    std::vector<std::string> order_again;
    for (const PlannedBlock& block : again.blocks) order_again.push_back(block.name);
    EXPECT_EQ(order, order_again);
  }
  EXPECT_GE(orders.size(), 4u);  // of 6 possible orders, 30 participants see most of them
}

TEST(ProtocolsSchedule, BalancedLatinSquareCounterbalancesPositionsAndCarryover) {
  // Issue 18: counterbalancing across participants. Every row a permutation; over the rows each
  // block in each position equally often, and each ordered pair of different blocks adjacent
  // equally often (Williams 1949): n rows for an even n, 2n for an odd n.
  for (int n = 1; n <= 8; ++n) {
    SCOPED_TRACE(n);
    const std::vector<std::vector<int>> rows = balanced_latin_square(n);
    ASSERT_EQ(rows.size(), size_t(n % 2 == 0 ? n : 2 * n));
    std::map<std::pair<int, int>, int> at_position, followed_by;
    for (const std::vector<int>& row : rows) {
      std::vector<int> sorted = row;
      std::sort(sorted.begin(), sorted.end());
      for (int i = 0; i < n; ++i) ASSERT_EQ(sorted[size_t(i)], i);
      for (int i = 0; i < n; ++i) ++at_position[{i, row[size_t(i)]}];
      for (int i = 1; i < n; ++i) ++followed_by[{row[size_t(i - 1)], row[size_t(i)]}];
    }
    const int times = int(rows.size()) / n;
    for (const auto& [key, count] : at_position) EXPECT_EQ(count, times);
    EXPECT_EQ(at_position.size(), size_t(n * n));
    if (n > 1) {
      EXPECT_EQ(followed_by.size(), size_t(n * (n - 1)));
      for (const auto& [pair, count] : followed_by)
        EXPECT_EQ(count, int(rows.size()) * (n - 1) / (n * (n - 1))) << pair.first << "," << pair.second;
    }
  }
}

TEST(ProtocolsSchedule, LatinSquareBlockOrderFollowsTheParticipantNumber) {
  Sections s;
  s.blocks = kThreeBlocks;  // primitives, columns, temple: an odd count, 6 rows
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 2\nblock_order = \"latin_square\"\n";
  const StudyConfig config = make_config(s);
  const std::vector<std::vector<int>> rows = balanced_latin_square(3);
  for (int p = 1; p <= 12; ++p) {
    char id[8];
    std::snprintf(id, sizeof id, "P%03d", p);
    const StudyPlan plan = make_study_plan(config, id);
    check_structure(plan);
    std::vector<std::string> order;
    for (const PlannedBlock& block : plan.blocks) order.push_back(block.name);
    std::vector<std::string> expected;
    for (int index : rows[size_t((p - 1) % 6)]) expected.push_back(config.blocks[size_t(index)].name);
    EXPECT_EQ(order, expected) << id;
  }
  EXPECT_EQ(participant_number("P007"), 7);
  EXPECT_EQ(participant_number("lab2-s12"), 12);
  EXPECT_EQ(participant_number("alice"), std::nullopt);
  EXPECT_THROW(make_study_plan(config, "alice"), InputError);
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 2\nblock_order = \"shuffled\"\n";
  EXPECT_THROW(make_config(s), InputError);
}

TEST(ProtocolsSchedule, BlockTrialsDoNotDependOnBlockPosition) {
  // Each block's trials come from a stream named after the block, so a block's own trial order is the
  // same whether the blocks are shuffled or not.
  Sections s;
  s.blocks = kThreeBlocks;
  const StudyPlan fixed = make_study_plan(make_config(s), "p07");
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 2\nblock_order = \"random\"\n";
  const StudyPlan random = make_study_plan(make_config(s), "p07");
  for (const PlannedBlock& block : fixed.blocks) {
    const auto other = std::find_if(random.blocks.begin(), random.blocks.end(),
                                    [&](const PlannedBlock& b) { return b.name == block.name; });
    ASSERT_NE(other, random.blocks.end());
    ASSERT_EQ(other->trial_count, block.trial_count);
    for (int i = 0; i < block.trial_count; ++i) {
      const Trial& a = fixed.trials[static_cast<size_t>(block.first_trial + i)];
      const Trial& b = random.trials[static_cast<size_t>(other->first_trial + i)];
      EXPECT_EQ(a.condition, b.condition);
      EXPECT_EQ(a.reference_first, b.reference_first);
    }
  }
}

// --- stimuli ----------------------------------------------------------------------------------------

TEST(ProtocolsSchedule, StimuliAreDistinctWithOneReferencePerBlock) {
  Sections s;
  s.stimulus_extra = kVariants;
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  check_structure(plan);
  // Per block: 1 reference + 5 levels x 2 variants.
  ASSERT_EQ(plan.stimuli.size(), 22u);
  std::set<std::tuple<std::string, bool, std::string, double>> seen;
  std::map<std::string, int> references_per_scene;
  for (const PlannedStimulus& stimulus : plan.stimuli) {
    EXPECT_TRUE(
        seen.insert({stimulus.spec.canonical(), stimulus.is_reference, stimulus.variant, stimulus.level.value_or(-1.0)})
            .second)
        << "duplicate " << stimulus.spec.canonical();
    if (stimulus.is_reference) {
      ++references_per_scene[stimulus.spec.scene];
      EXPECT_FALSE(stimulus.level.has_value());
      EXPECT_EQ(stimulus.variant, "");
    }
    // Every parameter of the method, defaults filled in, sizes from the config.
    EXPECT_EQ(stimulus.spec.method_name(), "gt");
    EXPECT_EQ(describe(stimulus.spec.method()).parameters.size(), 3u);
    EXPECT_EQ(stimulus.spec.width_px, 64);
    EXPECT_EQ(stimulus.spec.height_px, 48);
    EXPECT_EQ(stimulus.spec.frame_count, 5);
    EXPECT_DOUBLE_EQ(stimulus.spec.frames_per_second, 10.0);
    EXPECT_DOUBLE_EQ(stimulus.spec.camera_start_s, 1.0);
    if (!stimulus.is_reference) {
      EXPECT_DOUBLE_EQ(*parameter_value(stimulus.spec.parameters, "max_steps"), *stimulus.level);
      EXPECT_DOUBLE_EQ(*parameter_value(stimulus.spec.parameters, "hit_threshold"),
                       stimulus.variant == "coarse" ? 1.0 : 0.1);
    } else {
      EXPECT_DOUBLE_EQ(*parameter_value(stimulus.spec.parameters, "max_steps"), 256.0);
      EXPECT_DOUBLE_EQ(*parameter_value(stimulus.spec.parameters, "hit_threshold"), 0.25);
    }
    EXPECT_DOUBLE_EQ(*parameter_value(stimulus.spec.parameters, "samples_per_pixel"), 1.0);
  }
  EXPECT_EQ(references_per_scene, (std::map<std::string, int>{{"columns", 1}, {"primitives", 1}}));
  // All trials of a block share its reference.
  for (const PlannedBlock& block : plan.blocks) {
    std::set<int> references;
    for (int i = 0; i < block.trial_count; ++i)
      references.insert(plan.trials[static_cast<size_t>(block.first_trial + i)].reference);
    EXPECT_EQ(references.size(), 1u) << block.name;
  }
}

TEST(ProtocolsSchedule, RepeatedTrialsShareTheirStimuli) {
  Sections s;
  s.blocks = "[[block]]\nscene = \"primitives\"\n";
  s.protocol = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 8\n";
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  EXPECT_EQ(plan.stimuli.size(), 6u);  // 1 reference + 5 levels, however many repeats
  std::map<std::string, std::set<int>> tests_per_condition;
  for (const Trial& trial : plan.trials) {
    if (trial.attention_check) continue;
    tests_per_condition[trial.condition].insert(trial.reference_first ? trial.sequence[1] : trial.sequence[0]);
  }
  for (const auto& [condition, ids] : tests_per_condition) EXPECT_EQ(ids.size(), 1u) << condition;
}

TEST(ProtocolsSchedule, TwoBlocksOnOneSceneShareTheReferenceStimulus) {
  Sections s;
  s.blocks =
      "[[block]]\nscene = \"primitives\"\nname = \"first\"\n\n[[block]]\nscene = \"primitives\"\nname = \"second\"\n";
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  check_structure(plan);
  EXPECT_EQ(plan.stimuli.size(), 6u);
  ASSERT_EQ(plan.blocks.size(), 2u);
  EXPECT_EQ(plan.trials[0].reference, plan.trials.back().reference);
  // ... but their trials are shuffled by streams of their own.
  std::vector<std::string> first, second;
  for (int i = 0; i < plan.blocks[0].trial_count; ++i) first.push_back(plan.trials[static_cast<size_t>(i)].condition);
  for (int i = 0; i < plan.blocks[1].trial_count; ++i)
    second.push_back(plan.trials[static_cast<size_t>(plan.blocks[1].first_trial + i)].condition);
  EXPECT_NE(first, second);
}

TEST(ProtocolsSchedule, ATestIdenticalToTheReferenceIsStillATestStimulus) {
  // A level at the reference's own setting (GT, 256 steps) renders the same frames, but it is a test
  // stimulus with a level: it must not be merged with the reference.
  Sections s;
  s.levels = "[levels]\nparameter = \"max_steps\"\nvalues = [64, 256]\n";
  s.blocks = "[[block]]\nscene = \"primitives\"\n";
  s.attention.clear();
  const StudyPlan plan = make_study_plan(make_config(s), "p01");
  ASSERT_EQ(plan.stimuli.size(), 3u);
  for (const Trial& trial : plan.trials) {
    ASSERT_EQ(trial.sequence.size(), 2u);
    EXPECT_NE(trial.sequence[0], trial.sequence[1]) << describe(trial);
  }
}

// --- participants -------------------------------------------------------------------------------------

TEST(ProtocolsSchedule, ParticipantIds) {
  for (const std::string& bad :
       std::vector<std::string>{"../x", "a/b", "", "-x", std::string(65, 'a'), ".hidden", "a b", "a\\b", "ü", "p:1"}) {
    EXPECT_THROW(check_participant_id(bad), InputError) << "\"" << bad << "\"";
    EXPECT_THROW(check_new_participant_id(bad), InputError) << "\"" << bad << "\"";
  }
  // Reserved for new sessions (the report folder), still readable in an older build's log.
  for (const std::string reserved : {"analysis", "Analysis"}) {
    EXPECT_THROW(check_new_participant_id(reserved), InputError) << reserved;
    EXPECT_NO_THROW(check_participant_id(reserved)) << reserved;
  }
  for (const std::string& good : std::vector<std::string>{"P01", "a", "a_b-c", "x-", std::string(64, 'z'), "0"}) {
    EXPECT_NO_THROW(check_participant_id(good)) << "\"" << good << "\"";
  }
  const StudyConfig config = make_config(Sections{});
  EXPECT_THROW(make_study_plan(config, "../x"), InputError);
  EXPECT_THROW(make_study_plan(config, ""), InputError);
  try {
    check_participant_id("a/b");
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("a/b"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace fovlab
