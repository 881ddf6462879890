// --min-filter and --coarse-test on `fovlab bench` (and `render`): a flag given serves IPR and FIPR
// alike, as before; a flag left out leaves each method its own default, its descriptor's (log schema
// 10: the cone without the min filter, for IPR and FIPR alike). The sweep's command
// then leaves the flag out too, and the JSON gives each method's value; a run that gives both flags
// writes the JSON it wrote before.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/bench_flags.h"
#include "app/cli_support.h"
#include "bench/bench.h"

namespace fovlab {
namespace {

bench::BenchPlan plan_of(std::vector<std::string> extra) {
  std::vector<std::string> words = {"--scenes",  "primitives",  "--spp",     "1", "--width",     "64", "--height", "36",
                                    "--methods", "gt,ipr,fipr", "--refresh", "1", "--fovea-deg", "7.5"};
  words.insert(words.end(), extra.begin(), extra.end());
  return app::plan_bench(app::parse_bench_flags(words, "the flags"));
}

SphereTraceSettings method_settings(const bench::BenchPlan& plan, TraceMethod method) {
  SphereTraceSettings settings = plan.options.settings;
  settings.method = method;
  return bench::settings_of(plan.options, settings);
}

TEST(BenchPyramidDefaults, EachMethodTakesItsOwnDefaultUnlessAFlagGivesOne) {
  const bench::BenchPlan defaults = plan_of({});
  EXPECT_EQ(method_settings(defaults, TraceMethod::inverted_pyramid).coarse_test, CoarseTest::cone);
  EXPECT_EQ(method_settings(defaults, TraceMethod::inverted_pyramid).min_filter_size, 1);
  EXPECT_EQ(method_settings(defaults, TraceMethod::foveated_pyramid).coarse_test, CoarseTest::cone);
  EXPECT_EQ(method_settings(defaults, TraceMethod::foveated_pyramid).min_filter_size, 1);
  const std::string command = bench::sweep_command(defaults);
  EXPECT_EQ(command.find("--min-filter"), std::string::npos) << command;
  EXPECT_EQ(command.find("--coarse-test"), std::string::npos) << command;
  // The command plans the same sweep again (bench-merge reads it so).
  const bench::BenchPlan again = app::plan_bench(app::parse_sweep_command(command));
  EXPECT_EQ(method_settings(again, TraceMethod::inverted_pyramid).min_filter_size, 1);
  EXPECT_EQ(method_settings(again, TraceMethod::foveated_pyramid).coarse_test, CoarseTest::cone);

  const bench::BenchPlan given = plan_of({"--min-filter", "3", "--coarse-test", "ray"});
  for (TraceMethod method : {TraceMethod::inverted_pyramid, TraceMethod::foveated_pyramid}) {
    EXPECT_EQ(method_settings(given, method).coarse_test, CoarseTest::centre_ray);
    EXPECT_EQ(method_settings(given, method).min_filter_size, 3);
  }
  EXPECT_NE(bench::sweep_command(given).find(" --levels 3 --min-filter 3 --coarse-test ray --max-steps"),
            std::string::npos)
      << bench::sweep_command(given);

  const bench::BenchPlan one = plan_of({"--coarse-test", "ray"});
  EXPECT_EQ(method_settings(one, TraceMethod::inverted_pyramid).coarse_test, CoarseTest::centre_ray);
  EXPECT_EQ(method_settings(one, TraceMethod::inverted_pyramid).min_filter_size, 1);
  EXPECT_EQ(method_settings(one, TraceMethod::foveated_pyramid).min_filter_size, 1);
  EXPECT_EQ(method_settings(one, TraceMethod::foveated_pyramid).coarse_test, CoarseTest::centre_ray);
  EXPECT_EQ(method_settings(one, TraceMethod::ground_truth).min_filter_size, one.options.settings.min_filter_size);
}

TEST(BenchPyramidDefaults, TheJsonGivesEachMethodsValueWhereNoFlagGaveOne) {
  bench::BenchReport report;
  report.pyramids = {{bench::BenchMethod::ipr, {1, CoarseTest::cone}},
                     {bench::BenchMethod::fipr, {3, CoarseTest::centre_ray}}};
  report.min_filter_given = false;
  report.coarse_test_given = false;
  nlohmann::json json = bench::bench_report_json(report);
  EXPECT_EQ(json["min_filter_size"], (nlohmann::json{{"ipr", 1}, {"fipr", 3}}));
  EXPECT_EQ(json["coarse_test"], (nlohmann::json{{"ipr", "cone"}, {"fipr", "ray"}}));
  // Given on the command line: one value for both, as the JSON of earlier builds had it.
  report.settings.min_filter_size = 5;
  report.settings.coarse_test = CoarseTest::centre_ray;
  report.min_filter_given = true;
  report.coarse_test_given = true;
  json = bench::bench_report_json(report);
  EXPECT_EQ(json["min_filter_size"], 5);
  EXPECT_EQ(json["coarse_test"], "ray");
}

TEST(RenderPyramidDefaults, RenderTakesTheMethodsOwnDefaults) {
  SphereTraceSettings flags;  // the flags' values, none given
  flags.min_filter_size = 3;
  flags.coarse_test = CoarseTest::centre_ray;
  const app::PyramidFlagsGiven none;
  const SphereTraceSettings ipr = app::with_method_pyramid_defaults(flags, TraceMethod::inverted_pyramid, none);
  EXPECT_EQ(ipr.coarse_test, CoarseTest::cone);
  EXPECT_EQ(ipr.min_filter_size, 1);
  const SphereTraceSettings fipr = app::with_method_pyramid_defaults(flags, TraceMethod::foveated_pyramid, none);
  EXPECT_EQ(fipr.coarse_test, CoarseTest::cone);
  EXPECT_EQ(fipr.min_filter_size, 1);
  const SphereTraceSettings gt = app::with_method_pyramid_defaults(flags, TraceMethod::ground_truth, none);
  EXPECT_EQ(gt.coarse_test, CoarseTest::centre_ray);  // GT has no pyramid: as given
  EXPECT_EQ(gt.min_filter_size, 3);
  const SphereTraceSettings given =
      app::with_method_pyramid_defaults(flags, TraceMethod::inverted_pyramid, app::PyramidFlagsGiven{true, true});
  EXPECT_EQ(given.coarse_test, CoarseTest::centre_ray);
  EXPECT_EQ(given.min_filter_size, 3);
}

}  // namespace
}  // namespace fovlab
