// fovlab binomial: Ye et al. 2022's Table 2 checked from its counts (the stars match a one-sided test),
// and bad counts as one-line errors.
#include <gtest/gtest.h>

#include <string>

#include "tests/app/cli_test_support.h"

namespace {

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::run;

void expect_output(const std::string& arguments, const std::string& expected_line) {
  const CommandResult result = run("binomial " + arguments);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find(expected_line), std::string::npos) << arguments << ":\n" << result.out;
}

// Table 2 of Ye et al. 2022: 49, 47, 50 and 35 of 72 votes for RMFR. 47 of 72 is ** one-sided
// (p = 0.0064) but only * two-sided (0.0128): the paper's stars are one-sided.
TEST(BinomialCli, TableTwoOfYe2022FromItsCounts) {
  expect_output("47 72", "exact binomial p = 0.006387 **");
  expect_output("47 72", "47 of 72 (65.3 %), H0: p = 0.5, alternative greater");
  expect_output("47 72 --alternative two-sided", "exact binomial p = 0.01277 *");
  expect_output("49 72", "exact binomial p = 0.001471 **");
  expect_output("35 72 --alternative two-sided", "exact binomial p = 0.9063\n");
  expect_output("47 72", "95 % Clopper-Pearson interval of the share: [0.5314, 0.7612]");
  expect_output("0 10 --p0 0.2 --alternative less", "exact binomial p = 0.1074\n");  // 0.8^10
}

// A p-value a double cannot hold is printed as a bound with its log10, never as a subnormal: k = 0
// of n at p0 = 1/2, two-sided, is 2 / 2^n, log10 p = log10(2) - n log10(2).
TEST(BinomialCli, UnderflowingPValuesSayHowSmall) {
  expect_output("0 1000000 --alternative two-sided", "exact binomial p = < 1e-300 (log10 p = -301029.7) ***");
  expect_output("0 1000000000 --alternative two-sided", "exact binomial p = < 1e-300 (log10 p = -301029995.4) ***");
  expect_output("0 1000000000000 --alternative two-sided",
                "exact binomial p = < 1e-300 (log10 p = -301029995663.7) ***");
}

TEST(BinomialCli, BadCountsAreOneLineErrors) {
  expect_one_line_error(run("binomial x 72"), "K \"x\": expected a whole number");
  expect_one_line_error(run("binomial -3 72"), "K \"-3\": expected a whole number");
  expect_one_line_error(run("binomial 80 72"), "K 80: expected at most N = 72");
  expect_one_line_error(run("binomial 0 0"), "N 0: expected at least one trial");
  expect_one_line_error(run("binomial 5 10 --p0 1"), "--p0 1: expected a probability strictly between 0 and 1");
  expect_one_line_error(run("binomial 5 10 --confidence 95"), "--confidence 95: expected a level");
  expect_one_line_error(run("binomial 5 10 --alternative sideways"), "--alternative");
  expect_one_line_error(run("binomial 5 99999999999999999999"), "N \"99999999999999999999\": expected a whole number");
}

}  // namespace
