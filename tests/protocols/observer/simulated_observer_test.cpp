// Tests of protocols/observer/simulated_observer.h: the psychometric model (p_see, p_detect), the
// seeded answers of each protocol, their statistics, and parse_observer_spec.
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "protocols/stimuli/stimulus_settings.h"
#include "core/input_error.h"
#include "core/prng.h"
#include "study/config/study_config.h"
#include "protocols/observer/simulated_observer.h"
#include "study/schedule/study_plan.h"

namespace fovlab {
namespace {

StudyConfig make_config(const std::string& protocol, const std::string& levels, const std::string& attention = "") {
  const std::string text = R"([study]
name = "observer_test"
seed = 5

[display]
width_px = 64
height_px = 48
width_mm = 400
height_mm = 300
viewing_distance_mm = 600

[stimulus]
duration_s = 0.5
frames_per_second = 10

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "gt"

)" + levels + "\n" + protocol +
                           "\n" + attention + R"(
[[block]]
scene = "primitives"
)";
  return parse_study_config_text(text, "observer_test.toml", renderer_scene_catalog());
}

const std::string kLevels = "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16, 32, 64]\n";
const std::string kSame = "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 2\n";

// A comparison trial as the plan would make it, with any index.
Trial comparison(int index, std::optional<double> level, bool reference_first = true, bool attention_check = false) {
  Trial trial;
  trial.index = index;
  trial.level = attention_check ? std::nullopt : level;
  trial.attention_check = attention_check;
  trial.reference_first = reference_first;
  trial.condition = attention_check ? "attention_check" : "level";
  return trial;
}

ObserverModel model_with(uint64_t seed, double threshold, double slope, double guess, double lapse,
                         bool higher_is_better = true) {
  ObserverModel model;
  model.seed = seed;
  model.threshold = threshold;
  model.slope = slope;
  model.guess = guess;
  model.lapse = lapse;
  model.higher_is_better = higher_is_better;
  return model;
}

// --- the model -----------------------------------------------------------------------------------------

TEST(ProtocolsObserver, PSeeIsTheDocumentedLogistic) {
  ObserverModel model = model_with(0, 10.0, 2.0, 0.02, 0.02, /*higher_is_better=*/false);
  // Rising with the level when higher levels are worse.
  EXPECT_DOUBLE_EQ(model.p_see(10.0), 0.5);
  EXPECT_NEAR(model.p_see(11.0), 1.0 / (1.0 + std::exp(-2.0)), 1e-15);
  EXPECT_NEAR(model.p_see(11.0), 0.88079707797788243, 1e-12);
  EXPECT_NEAR(model.p_see(9.0), 0.11920292202211757, 1e-12);
  EXPECT_LT(model.p_see(-100.0), 1e-12);
  EXPECT_GT(model.p_see(100.0), 1.0 - 1e-12);
  EXPECT_EQ(model.p_see(std::nullopt), 0.0);

  // Mirrored when higher levels are better: p_see falls as the level grows.
  model.higher_is_better = true;
  EXPECT_DOUBLE_EQ(model.p_see(10.0), 0.5);
  EXPECT_NEAR(model.p_see(11.0), 0.11920292202211757, 1e-12);
  EXPECT_NEAR(model.p_see(9.0), 0.88079707797788243, 1e-12);
  EXPECT_GT(model.p_see(-100.0), 1.0 - 1e-12);
  EXPECT_LT(model.p_see(100.0), 1e-12);
  EXPECT_EQ(model.p_see(std::nullopt), 0.0);
  for (double x = -5.0; x <= 25.0; x += 0.5) {
    ObserverModel mirrored = model;
    mirrored.higher_is_better = false;
    EXPECT_NEAR(model.p_see(x) + mirrored.p_see(x), 1.0, 1e-12) << x;
    EXPECT_NEAR(model.p_see(10.0 - (x - 10.0)), mirrored.p_see(x), 1e-12) << x;
  }
}

TEST(ProtocolsObserver, PDetectAddsGuessAndLapse) {
  ObserverModel model = model_with(0, 10.0, 2.0, 0.02, 0.02);
  EXPECT_DOUBLE_EQ(model.p_detect(10.0), 0.02 + 0.96 * 0.5);
  EXPECT_DOUBLE_EQ(model.p_detect(std::nullopt), 0.02);  // identical stimuli: false alarms only
  EXPECT_NEAR(model.p_detect(-1000.0), 0.98, 1e-12);     // plainly visible: all but lapses
  EXPECT_NEAR(model.p_detect(1000.0), 0.02, 1e-12);      // invisible: guesses only
  model.guess = 0.1;
  model.lapse = 0.05;
  EXPECT_DOUBLE_EQ(model.p_detect(10.0), 0.1 + 0.85 * 0.5);
  EXPECT_NEAR(model.p_detect(9.0), 0.1 + 0.85 * 0.88079707797788243, 1e-12);
  EXPECT_DOUBLE_EQ(model.p_detect(std::nullopt), 0.1);
  // Monotonic in the level, falling when higher is better.
  for (double x = 0.0; x < 20.0; x += 0.25) EXPECT_GE(model.p_detect(x), model.p_detect(x + 0.25)) << x;
}

// --- answers --------------------------------------------------------------------------------------------

TEST(ProtocolsObserver, AnswersAreDeterministicPerTrial) {
  const StudyPlan plan = make_study_plan(make_config(kSame, kLevels), "p01");
  const ObserverModel model = parse_observer_spec("simulated", plan);
  const SimulatedObserver a(model, plan), b(model, plan);
  int differences_from_other_seed = 0;
  ObserverModel other_model = model;
  other_model.seed = model.seed + 1;
  const SimulatedObserver other(other_model, plan);
  for (const Trial& trial : plan.trials) {
    const ObserverAnswer first = a.answer_comparison(trial);
    const ObserverAnswer again = a.answer_comparison(trial);
    const ObserverAnswer twin = b.answer_comparison(trial);
    EXPECT_EQ(first.answer, again.answer);
    EXPECT_EQ(first.response_time_s, again.response_time_s);
    EXPECT_EQ(first.answer, twin.answer);
    EXPECT_EQ(first.response_time_s, twin.response_time_s);
    EXPECT_TRUE(first.answer == "same" || first.answer == "different") << first.answer;
    differences_from_other_seed += other.answer_comparison(trial).response_time_s != first.response_time_s;
  }
  // Another seed, other draws (response times are continuous, so nearly all differ).
  EXPECT_GE(differences_from_other_seed, static_cast<int>(plan.trials.size()) - 1);
  // The answer of a trial depends on its index, not on the order in which trials are asked.
  const Trial& last = plan.trials.back();
  const SimulatedObserver fresh(model, plan);
  EXPECT_EQ(fresh.answer_comparison(last).response_time_s, a.answer_comparison(last).response_time_s);
}

TEST(ProtocolsObserver, IdenticalStimuliAreMostlySame) {
  const StudyPlan plan = make_study_plan(make_config(kSame, kLevels), "p01");
  const ObserverModel model = model_with(11, 34.0, 8.0 / 60.0, 0.02, 0.02);
  const SimulatedObserver observer(model, plan);
  constexpr int n = 5000;
  int different = 0;
  for (int i = 0; i < n; ++i)
    different += observer.answer_comparison(comparison(i, std::nullopt, true, true)).answer == "different";
  // Binomial(5000, 0.02): mean 100, sd 9.9.
  EXPECT_GT(different, 100 - 45);
  EXPECT_LT(different, 100 + 45);
}

TEST(ProtocolsObserver, ShareOfDifferentMatchesPDetect) {
  const StudyPlan plan = make_study_plan(make_config(kSame, kLevels), "p01");
  const ObserverModel defaults = parse_observer_spec("simulated", plan);  // threshold 34, slope 8/60
  for (double level : {4.0, 16.0, 34.0, 50.0, 64.0}) {
    int different = 0, n = 0;
    for (uint64_t seed = 0; seed < 20; ++seed) {
      ObserverModel model = defaults;
      model.seed = seed;
      const SimulatedObserver observer(model, plan);
      for (int i = 0; i < 200; ++i, ++n)
        different += observer.answer_comparison(comparison(i, level, i % 2 == 0)).answer == "different";
    }
    const double p = defaults.p_detect(level);
    const double tolerance = 4.5 * std::sqrt(p * (1 - p) / n);
    EXPECT_NEAR(double(different) / n, p, tolerance) << "level " << level << " p_detect " << p;
  }
}

TEST(ProtocolsObserver, AComparisonWithoutLevelsIsSeenAsAtLevelZero) {
  const StudyPlan plan = make_study_plan(make_config(kSame, ""), "p01");
  // Without levels the threshold defaults to 0: p_detect(0) = 0.02 + 0.96 * 0.5 = 0.5.
  const ObserverModel model = parse_observer_spec("simulated", plan);
  EXPECT_DOUBLE_EQ(model.threshold, 0.0);
  EXPECT_DOUBLE_EQ(model.slope, 1.0);
  const SimulatedObserver observer(model, plan);
  constexpr int n = 4000;
  int different = 0;
  for (int i = 0; i < n; ++i)
    different += observer.answer_comparison(comparison(i, std::nullopt)).answer == "different";
  EXPECT_NEAR(double(different) / n, 0.5, 4.5 * std::sqrt(0.25 / n));
}

TEST(ProtocolsObserver, TwoAfcBetterChoosesTheReferenceWhenItSeesADifference) {
  const StudyPlan plan =
      make_study_plan(make_config("[protocol]\nkind = \"2afc\"\nquestion = \"better\"\nrepeats = 2\n", kLevels), "p01");
  // Always seen (guess 0, lapse 0, far below threshold): the reference's interval is chosen.
  const SimulatedObserver sees(model_with(3, 1000.0, 1.0, 0.0, 0.0), plan);
  for (int i = 0; i < 200; ++i) {
    EXPECT_EQ(sees.answer_comparison(comparison(i, 4.0, true)).answer, "first");
    EXPECT_EQ(sees.answer_comparison(comparison(i, 4.0, false)).answer, "second");
  }
  // Never seen: a coin flip.
  const SimulatedObserver blind(model_with(3, -1000.0, 1.0, 0.0, 0.0), plan);
  int first = 0;
  constexpr int n = 4000;
  for (int i = 0; i < n; ++i) {
    const std::string answer = blind.answer_comparison(comparison(i, 4.0, i % 2 == 0)).answer;
    ASSERT_TRUE(answer == "first" || answer == "second") << answer;
    first += answer == "first";
  }
  EXPECT_NEAR(double(first) / n, 0.5, 4.5 * std::sqrt(0.25 / n));
}

TEST(ProtocolsObserver, PairAnswers) {
  const StudyPlan plan = make_study_plan(make_config("[protocol]\nkind = \"pair\"\nrepeats = 2\n", kLevels), "p01");
  const SimulatedObserver sees(model_with(4, 1000.0, 1.0, 0.0, 0.0), plan);
  const SimulatedObserver blind(model_with(4, -1000.0, 1.0, 0.0, 0.0), plan);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(sees.answer_comparison(comparison(i, 8.0, true)).answer, "first");
    EXPECT_EQ(sees.answer_comparison(comparison(i, 8.0, false)).answer, "second");
    EXPECT_EQ(blind.answer_comparison(comparison(i, 8.0, true)).answer, "same");
    // Identical stimuli with guess 0: always "same", even for an observer that sees everything else.
    EXPECT_EQ(sees.answer_comparison(comparison(i, std::nullopt, true, true)).answer, "same");
  }
}

TEST(ProtocolsObserver, RatingAnswers) {
  const StudyPlan plan = make_study_plan(make_config("[protocol]\nkind = \"rating\"\nrepeats = 2\n", kLevels), "p01");
  const SimulatedObserver sees(model_with(5, 1000.0, 1.0, 0.0, 0.0), plan);
  const SimulatedObserver blind(model_with(5, -1000.0, 1.0, 0.0, 0.0), plan);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(sees.answer_comparison(comparison(i, 8.0)).answer, "1");   // plainly visible: significant
    EXPECT_EQ(blind.answer_comparison(comparison(i, 8.0)).answer, "3");  // not seen: identical
    EXPECT_EQ(sees.answer_comparison(comparison(i, std::nullopt, true, true)).answer, "3");
  }
  // At the threshold (guess 0, lapse 0): P(3) = 0.5, P(1) = P(2) = 0.25.
  const SimulatedObserver half(model_with(5, 8.0, 1.0, 0.0, 0.0), plan);
  std::map<std::string, int> counts;
  constexpr int n = 4000;
  for (int i = 0; i < n; ++i) ++counts[half.answer_comparison(comparison(i, 8.0)).answer];
  EXPECT_EQ(counts.size(), 3u);
  EXPECT_NEAR(double(counts["3"]) / n, 0.5, 4.5 * std::sqrt(0.25 / n));
  EXPECT_NEAR(double(counts["1"]) / n, 0.25, 4.5 * std::sqrt(0.1875 / n));
  EXPECT_NEAR(double(counts["2"]) / n, 0.25, 4.5 * std::sqrt(0.1875 / n));
}

TEST(ProtocolsObserver, ResponseTimes) {
  const StudyPlan plan = make_study_plan(make_config(kSame, kLevels), "p01");
  ObserverModel model = model_with(6, 34.0, 0.1, 0.02, 0.02);
  model.mean_response_s = 0.8;
  const SimulatedObserver observer(model, plan);
  constexpr int n = 4000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double t = observer.answer_comparison(comparison(i, 16.0)).response_time_s;
    ASSERT_GE(t, 0.3);
    sum += t;
  }
  // 0.3 s + exponential with mean 0.5 s: mean 0.8 s, sd 0.5 s.
  EXPECT_NEAR(sum / n, 0.8, 4.5 * 0.5 / std::sqrt(double(n)));

  model.mean_response_s = 0.2;  // below the 0.3 s floor: the floor is the mean itself
  const SimulatedObserver quick(model, plan);
  for (int i = 0; i < 100; ++i) {
    const double t = quick.answer_comparison(comparison(i, 16.0)).response_time_s;
    EXPECT_GE(t, 0.2);
    EXPECT_LT(t, 0.25);
  }
}

// --- ramp and slider --------------------------------------------------------------------------------------

// An observer that sees levels below 10 for sure and levels above 10 never (guess 0, lapse 0).
ObserverModel sharp_model() { return model_with(9, 10.0, 100.0, 0.0, 0.0, /*higher_is_better=*/true); }

TEST(ProtocolsObserver, RampStepAnswers) {
  const StudyPlan plan = make_study_plan(make_config("[protocol]\nkind = \"ramp\"\ntrial_order = \"fixed\"\n",
                                                     "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16, 32]\n"),
                                         "p01");
  ASSERT_EQ(plan.trials.size(), 2u);
  const Trial& up = plan.trials[0];    // 4, 8, 16, 32, reference
  const Trial& down = plan.trials[1];  // reference, 32, 16, 8, 4
  ASSERT_TRUE(up.ramp_toward_reference);
  ASSERT_FALSE(down.ramp_toward_reference);
  const SimulatedObserver observer(sharp_model(), plan);
  std::vector<std::string> up_answers, down_answers;
  for (int step = 1; step <= 4; ++step) {
    up_answers.push_back(observer.answer_ramp_step(up, step).answer);
    down_answers.push_back(observer.answer_ramp_step(down, step).answer);
    EXPECT_GE(observer.answer_ramp_step(up, step).response_time_s, 0.3);
    EXPECT_EQ(observer.answer_ramp_step(up, step).response_time_s, observer.answer_ramp_step(up, step).response_time_s);
  }
  // Below the threshold every step changes how much degradation is visible (4 -> 8 -> 16: quality
  // increased); above it nothing is visible (16 -> 32 -> reference: same). Issue 18: the observer
  // used to answer "same" between two degraded stimuli, so a ramp's threshold came out at its
  // most degraded level whatever the truth.
  EXPECT_EQ(up_answers, (std::vector<std::string>{"increased", "increased", "same", "same"}));
  EXPECT_EQ(down_answers, (std::vector<std::string>{"same", "same", "decreased", "decreased"}));
}

TEST(ProtocolsObserver, RampAndComparisonAreOneModel) {
  // Against the reference, a ramp step is seen exactly as often as a comparison trial's difference:
  // 1 - exp(-v(x)) = p_see(x); v is 0 for the reference, grows on the degraded side, and is
  // monotone in the level, for both directions of the level axis.
  for (bool higher_is_better : {true, false}) {
    const ObserverModel model = model_with(9, 12.0, 0.5, 0.02, 0.02, higher_is_better);
    EXPECT_EQ(model.visible_degradation(std::nullopt), 0.0);
    double previous = -1.0;
    for (double level = -40.0; level <= 60.0; level += 0.5) {
      SCOPED_TRACE(level);
      const double v = model.visible_degradation(level);
      EXPECT_NEAR(-std::expm1(-v), model.p_see(level), 1e-12);
      EXPECT_TRUE(std::isfinite(v));
      if (previous >= 0.0) {
        if (higher_is_better) EXPECT_LE(v, previous);
        else EXPECT_GE(v, previous);
      }
      previous = v;
    }
  }
  // Far on the degraded side v grows by slope per level unit: neighbours 5 apart differ by 2.5.
  const ObserverModel model = model_with(9, 12.0, 0.5, 0.0, 0.0, true);
  EXPECT_NEAR(model.visible_degradation(-10.0) - model.visible_degradation(-5.0), 2.5, 1e-3);
}

TEST(ProtocolsObserver, SliderActions) {
  const StudyPlan plan = make_study_plan(
      make_config("[protocol]\nkind = \"slider\"\n", "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8, 16, 32]\n"),
      "p01");
  ASSERT_EQ(plan.trials.size(), 1u);
  const Trial& trial = plan.trials[0];  // ladder 4, 8, 16, 32
  const SimulatedObserver observer(sharp_model(), plan);
  EXPECT_EQ(observer.answer_slider(trial, 0, 0).answer, "reference");  // looks at the reference first
  EXPECT_EQ(observer.answer_slider(trial, 1, 0).answer, "up");         // 4 steps: degraded, move up
  EXPECT_EQ(observer.answer_slider(trial, 2, 1).answer, "up");         // 8 steps: still degraded
  EXPECT_EQ(observer.answer_slider(trial, 3, 2).answer, "save");       // 16 steps: matches
  EXPECT_EQ(observer.answer_slider(trial, 4, 3).answer, "save");
  // An observer that sees every level still saves at the top of the ladder (it cannot go higher).
  const SimulatedObserver picky(model_with(9, 1000.0, 1.0, 0.0, 0.0), plan);
  EXPECT_EQ(picky.answer_slider(trial, 1, 2).answer, "up");
  EXPECT_EQ(picky.answer_slider(trial, 1, 3).answer, "save");
  EXPECT_GE(observer.answer_slider(trial, 1, 0).response_time_s, 0.3);
  EXPECT_EQ(observer.answer_slider(trial, 1, 0).response_time_s, observer.answer_slider(trial, 1, 0).response_time_s);
}

// --- parse_observer_spec -----------------------------------------------------------------------------------

TEST(ProtocolsObserver, SpecDefaults) {
  const StudyPlan plan = make_study_plan(make_config(kSame, kLevels), "p01");
  const ObserverModel model = parse_observer_spec("simulated", plan);
  EXPECT_DOUBLE_EQ(model.threshold, 34.0);    // middle of 4..64
  EXPECT_DOUBLE_EQ(model.slope, 8.0 / 60.0);  // 8 / range
  EXPECT_DOUBLE_EQ(model.guess, 0.02);
  EXPECT_DOUBLE_EQ(model.lapse, 0.02);
  EXPECT_DOUBLE_EQ(model.mean_response_s, 0.8);
  EXPECT_TRUE(model.higher_is_better);
  EXPECT_EQ(model.seed, derive_seed(plan.session_seed, "observer"));
  // Another participant, another default seed.
  const StudyPlan other = make_study_plan(make_config(kSame, kLevels), "p02");
  EXPECT_NE(parse_observer_spec("simulated", other).seed, model.seed);

  const StudyPlan lower = make_study_plan(
      make_config(kSame, "[levels]\nparameter = \"max_steps\"\nvalues = [10, 20]\nhigher_is_better = false\n"), "p01");
  const ObserverModel lower_model = parse_observer_spec("simulated", lower);
  EXPECT_FALSE(lower_model.higher_is_better);
  EXPECT_DOUBLE_EQ(lower_model.threshold, 15.0);
  EXPECT_DOUBLE_EQ(lower_model.slope, 0.8);

  const StudyPlan no_levels = make_study_plan(make_config(kSame, ""), "p01");
  const ObserverModel flat = parse_observer_spec("simulated", no_levels);
  EXPECT_DOUBLE_EQ(flat.threshold, 0.0);
  EXPECT_DOUBLE_EQ(flat.slope, 1.0);
}

TEST(ProtocolsObserver, SpecOverrides) {
  const StudyPlan plan = make_study_plan(make_config(kSame, kLevels), "p01");
  const ObserverModel model =
      parse_observer_spec("simulated:threshold=7.5,slope=1,guess=0.05,lapse=0.01,rt=0.9,seed=3", plan);
  EXPECT_DOUBLE_EQ(model.threshold, 7.5);
  EXPECT_DOUBLE_EQ(model.slope, 1.0);
  EXPECT_DOUBLE_EQ(model.guess, 0.05);
  EXPECT_DOUBLE_EQ(model.lapse, 0.01);
  EXPECT_DOUBLE_EQ(model.mean_response_s, 0.9);
  EXPECT_EQ(model.seed, 3u);
  EXPECT_TRUE(model.higher_is_better);
  // Only some keys: the rest keep their defaults.
  const ObserverModel partial = parse_observer_spec("simulated:guess=0,threshold=-2", plan);
  EXPECT_DOUBLE_EQ(partial.guess, 0.0);
  EXPECT_DOUBLE_EQ(partial.threshold, -2.0);
  EXPECT_DOUBLE_EQ(partial.slope, 8.0 / 60.0);
  EXPECT_EQ(partial.seed, derive_seed(plan.session_seed, "observer"));
}

TEST(ProtocolsObserver, SpecSeedKeepsAll64Bits) {
  // Seeds are logged as 64-bit integers (session header); giving one back must reproduce it exactly.
  const StudyPlan plan = make_study_plan(make_config(kSame, kLevels), "p01");
  EXPECT_EQ(parse_observer_spec("simulated:seed=9007199254740993", plan).seed, 9007199254740993ULL);  // 2^53 + 1
  const uint64_t logged = derive_seed(plan.session_seed, "observer");
  EXPECT_EQ(parse_observer_spec("simulated:seed=" + std::to_string(logged), plan).seed, logged);
}

TEST(ProtocolsObserver, SpecErrors) {
  const StudyPlan plan = make_study_plan(make_config(kSame, kLevels), "p01");
  struct Case {
    std::string spec;
    std::string named;  // the message must contain this
  };
  const std::vector<Case> cases = {
      {"simulatedx", "simulatedx"},
      {"human", "human"},
      {"", "simulated"},
      {"simulated:foo=1", "foo"},
      {"simulated:slope=0", "slope"},
      {"simulated:slope=-1", "slope"},
      {"simulated:guess=1", "guess"},
      {"simulated:guess=-0.1", "guess"},
      {"simulated:lapse=1.5", "lapse"},
      {"simulated:rt=0", "rt"},
      {"simulated:seed=1.5", "seed"},
      {"simulated:seed=-1", "seed"},
      {"simulated:threshold=abc", "threshold"},
      {"simulated:threshold=", "threshold"},
      {"simulated:threshold", "threshold"},
      {"simulated:threshold=1x", "threshold"},
      {"simulated:threshold=nan", "threshold"},
      {"simulated:threshold=inf", "threshold"},
      {"simulated:guess=0.5,lapse=0.5", "guess + lapse"},
  };
  for (const Case& c : cases) {
    try {
      parse_observer_spec(c.spec, plan);
      ADD_FAILURE() << "no error for \"" << c.spec << "\"";
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(c.named), std::string::npos) << c.spec << " -> " << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
      EXPECT_EQ(message.rfind("--observer: ", 0), 0u) << message;
    } catch (const std::exception& error) {
      ADD_FAILURE() << "not an InputError for \"" << c.spec << "\": " << error.what();
    }
  }
  // guess 0.7 with the default lapse 0.02 is valid; with lapse 0.3 the sum reaches 1.
  EXPECT_DOUBLE_EQ(parse_observer_spec("simulated:guess=0.7", plan).guess, 0.7);
  EXPECT_THROW(parse_observer_spec("simulated:guess=0.7,lapse=0.3", plan), InputError);
}

}  // namespace
}  // namespace fovlab
