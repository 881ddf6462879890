// fovlab simulate prints, per group, the headline `fovlab analyze` would give its simulated
// participants' answers beside what the headline's method aims at for those observers
// (bench/procedure_simulation.h): for the shipped pilots of the adaptive procedures and of the
// ramp and the slider, the interval holds the aim.
#include <gtest/gtest.h>

#include <string>

#include "tests/app/cli_test_support.h"

namespace fovlab {
namespace {

void expect_every_headline_holds_its_aim(const std::string& experiment, const std::string& observer) {
  const auto result =
      cli_test::run("simulate " + std::string(FOVLAB_SOURCE_DIR) + "/experiments/" + experiment +
                    " --participants 20 --threads 2" + (observer.empty() ? "" : " --observer " + observer));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const size_t table = result.out.find("headline per group");
  ASSERT_NE(table, std::string::npos) << result.out;
  const std::string headlines = result.out.substr(table);
  std::printf("%s", headlines.c_str());
  EXPECT_NE(headlines.find("inside the interval"), std::string::npos) << headlines;
  EXPECT_EQ(headlines.find("OUTSIDE"), std::string::npos) << headlines;
  EXPECT_EQ(headlines.find("not estimable"), std::string::npos) << headlines;
}

TEST(SimulateHeadline, QuestPlusPilot) {
  expect_every_headline_holds_its_aim("pilot_simulated_quest.toml", "simulated:threshold=14,slope=0.4");
}
TEST(SimulateHeadline, StaircasePilot) {
  expect_every_headline_holds_its_aim("pilot_simulated_staircase.toml", "simulated:threshold=14,slope=0.4");
}
TEST(SimulateHeadline, RampPilot) { expect_every_headline_holds_its_aim("fpt_ramp.toml", ""); }
TEST(SimulateHeadline, SliderPilot) { expect_every_headline_holds_its_aim("fpt_slider.toml", ""); }

// A design whose levels cannot reach the observers' threshold says so instead of giving a number.
TEST(SimulateHeadline, UnreachableLevelsAreNotEstimable) {
  const auto result = cli_test::run(
      "simulate " + std::string(FOVLAB_SOURCE_DIR) +
      "/experiments/fpt_pair.toml --participants 10 --threads 2 --observer simulated:threshold=80,slope=1");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("not estimable"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("lies outside the tested levels"), std::string::npos) << result.out;
}

}  // namespace
}  // namespace fovlab
