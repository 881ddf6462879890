// fovlab bench --step-breakdown: GT's and IPR's rows gain "step_breakdown" (categories summing to
// the top level's steps) and the table "Where the steps go"; without the flag neither appears, and
// every other field of the report is the same. Speed is reported, never asserted.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::read_all;
using fovlab::cli_test::run;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-step-breakdown-cli-test"); }

// Times (and what is made of them) may differ between two runs of one sweep.
bool timed(const std::string& key) {
  for (const char* part : {"ms", "speedup", "over_floor", "pareto"})
    if (key.find(part) != std::string::npos) return true;
  return false;
}

// `with` is `without` plus "step_breakdown" in GT's and IPR's runs and the flag in the sweep's
// command, times aside.
void expect_same_but_breakdown(const nlohmann::json& without, const nlohmann::json& with, const std::string& path) {
  if (without.is_object()) {
    ASSERT_TRUE(with.is_object()) << path;
    for (const auto& [key, value] : with.items()) {
      if (key == "step_breakdown" || timed(key)) continue;
      ASSERT_TRUE(without.contains(key)) << path << "." << key;
    }
    for (const auto& [key, value] : without.items()) {
      EXPECT_NE(key, "step_breakdown") << path;
      if (timed(key)) continue;
      ASSERT_TRUE(with.contains(key)) << path << "." << key;
      if (key == "command") {  // the sweep's has the flag; a cell's reproduces its timings without it
        std::string command = with[key].get<std::string>();
        const size_t flag = command.find(" --step-breakdown");
        if (flag != std::string::npos) command.erase(flag, std::string(" --step-breakdown").size());
        EXPECT_EQ(command, value.get<std::string>()) << path;
        continue;
      }
      expect_same_but_breakdown(value, with[key], path + "." + key);
    }
    return;
  }
  if (without.is_array()) {
    ASSERT_TRUE(with.is_array()) << path;
    ASSERT_EQ(with.size(), without.size()) << path;
    for (size_t i = 0; i < without.size(); ++i)
      expect_same_but_breakdown(without[i], with[i], path + "[" + std::to_string(i) + "]");
    return;
  }
  EXPECT_EQ(with, without) << path;
}

TEST(BenchCli, StepBreakdownAddsItsTableAndKeyOnlyWhenAsked) {
  const fs::path dir = scratch();
  const std::string sweep = "bench --scenes primitives --spp 1,16 --width 32 --height 18 --repeats 1 --methods gt,ipr";
  const CommandResult plain = run(sweep + " --json " + (dir / "plain.json").string());
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const CommandResult counted = run(sweep + " --step-breakdown --json " + (dir / "counted.json").string());
  ASSERT_EQ(counted.exit_code, 0) << counted.err;
  EXPECT_EQ(plain.out.find("Where the steps go"), std::string::npos);
  EXPECT_NE(counted.out.find("Where the steps go"), std::string::npos);

  const nlohmann::json without = nlohmann::json::parse(read_all(dir / "plain.json"));
  const nlohmann::json with = nlohmann::json::parse(read_all(dir / "counted.json"));
  expect_same_but_breakdown(without, with, "");
  EXPECT_NE(with["command"].get<std::string>().find(" --step-breakdown"), std::string::npos);
  ASSERT_EQ(with["rows"].size(), 2u);
  for (const nlohmann::json& row : with["rows"]) {
    EXPECT_FALSE(row["floor"].contains("step_breakdown"));
    for (const char* method : {"gt", "ipr"}) {
      ASSERT_TRUE(row[method].contains("step_breakdown")) << method;
      const nlohmann::json& breakdown = row[method]["step_breakdown"];
      uint64_t sum = 0;
      for (const auto& [name, category] : breakdown["categories"].items()) sum += category["steps"].get<uint64_t>();
      EXPECT_EQ(sum, breakdown["total_steps"].get<uint64_t>()) << method;
      EXPECT_EQ(breakdown["samples"].get<uint64_t>(), 32u * 18u * row["spp"].get<uint64_t>()) << method;
      // GT has one level, so its top level's steps are all of its steps; IPR's levels below add theirs.
      if (std::string(method) == "gt") {
        EXPECT_EQ(sum, row["gt"]["total_steps"].get<uint64_t>());
      } else {
        EXPECT_LT(sum, row["ipr"]["total_steps"].get<uint64_t>());
      }
    }
  }
}

}  // namespace
