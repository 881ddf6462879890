// The pilot without people (experiments/pilot_simulated.toml): ten simulated participants whose
// psychometric function has a known threshold (14 steps). `fovlab analyze` must recover it: the
// logistic fit's 95 % profile-likelihood interval holds the truth, and the report files are written.
#include <gtest/gtest.h>

#include <filesystem>

#include "analysis/study/study_analysis.h"
#include "tests/app/cli_test_support.h"

namespace fovlab::analysis {
namespace {

namespace fs = std::filesystem;
using fovlab::cli_test::CommandResult;

constexpr double true_threshold = 14.0;

// One test, so the ten sessions run once (CTest runs every test in a process of its own).
TEST(PilotRecovery, AnalyzeRecoversTheTrueThresholdAndLeavesTheLogsAsTheyWere) {
  const fs::path results = fovlab::cli_test::scratch("fovlab-pilot-recovery");
  const std::string config = std::string(FOVLAB_SOURCE_DIR) + "/experiments/pilot_simulated.toml";
  for (int i = 0; i < 10; ++i) {
    const CommandResult run =
        fovlab::cli_test::run("run " + config + " --participant next --headless --results " + results.string() +
                                  " --observer simulated:threshold=14,slope=0.4,guess=0.02,lapse=0.02",
                              "env -u DISPLAY -u WAYLAND_DISPLAY");
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }

  // The logistic fit's 95 % interval holds the true threshold.
  const StudyData data = load_study({results.string()});
  ASSERT_EQ(data.participants.size(), 10u);
  EXPECT_TRUE(data.left_out.empty());
  AnalysisOptions options;
  options.bootstrap_samples = 400;
  options.shapes = {PsychometricShape::logistic};
  const AnalysisResult result = analyse_study(data, options);
  ASSERT_EQ(result.fits.size(), 1u);
  ASSERT_EQ(result.fits[0].fits.size(), 1u);
  const PsychometricFit& fit = result.fits[0].fits[0];
  EXPECT_TRUE(fit.converged);
  EXPECT_LE(fit.threshold_interval.lower, true_threshold);
  EXPECT_GE(fit.threshold_interval.upper, true_threshold);
  // And the interval is informative, not the whole level range.
  EXPECT_LT(fit.threshold_interval.upper - fit.threshold_interval.lower, 8.0);
  EXPECT_FALSE(fit.model.rising);  // more steps look more like the reference
  // 800 comparison trials in 8 conditions.
  uint64_t trials = 0;
  for (const ConditionRow& row : result.conditions) trials += row.n;
  EXPECT_EQ(trials, 800u);

  // The command writes the report and leaves the logs as they were.
  const fs::path log = results / "pilot_simulated" / "P001" / "events.jsonl";
  const std::string before = fovlab::cli_test::read_all(log);
  const fs::path out = fovlab::cli_test::scratch("fovlab-pilot-recovery-out");
  const CommandResult analyzed = fovlab::cli_test::run("analyze " + (results / "pilot_simulated").string() +
                                                       " --bootstrap 100 --out " + out.string());
  ASSERT_EQ(analyzed.exit_code, 0) << analyzed.err;
  for (const char* file : {"thresholds.json", "conditions.csv", "participants.csv", "report.html"})
    EXPECT_TRUE(fs::is_regular_file(out / file)) << file;
  EXPECT_NE(analyzed.out.find("logistic"), std::string::npos) << analyzed.out;
  EXPECT_EQ(fovlab::cli_test::read_all(log), before);
}

}  // namespace
}  // namespace fovlab::analysis
