// bench's vocabulary and plan: every method's --methods word reads back as the method (the sampling
// models' words are foveation's), and a plan's unit holds its cells in the order they are measured
// (GT, IPR, every FIPR variant, every sampling map), as sweep_layout hands them to bench-merge.
#include <gtest/gtest.h>

#include <string>

#include "bench/bench.h"

namespace fovlab::bench {
namespace {

TEST(BenchMethod, EveryNameReadsBackAsItsMethod) {
  for (const BenchMethodName& entry : bench_method_names()) {
    EXPECT_EQ(parse_bench_method(entry.name), entry.method) << entry.name;
    EXPECT_STREQ(bench_method_name(entry.method), entry.name);
    if (const std::optional<SamplingModel> model = sampling_model_of(entry.method)) {
      EXPECT_STREQ(sampling_model_name(*model), entry.name);
      EXPECT_EQ(bench_method_of(*model), entry.method);
    }
  }
  EXPECT_EQ(bench_method_names().size(), 3 + kSamplingModelCount);  // gt, ipr, fipr and each model
  EXPECT_EQ(parse_bench_method("kfr"), bench_method_of(SamplingModel::kernel_log_polar));
  EXPECT_FALSE(parse_bench_method("rtx"));
  EXPECT_FALSE(parse_bench_method("GT"));
}

TEST(BenchPlan, AUnitsCellsAreInTheOrderMeasured) {
  BenchOptions options;
  options.scenes = {"primitives", "columns"};
  options.spps = {1, 4};
  options.times_s = {0.0f, 9.0f};
  options.methods = {BenchMethod::gt, BenchMethod::fipr, BenchMethod::ipr};
  options.refreshes = {1, 2};
  options.fovea_degs = {7.5};
  options.variants = {{1, 7.5, {}}, {2, 7.5, {}}};
  const BenchPlan plan = plan_bench(options);
  EXPECT_TRUE(plan.ipr);
  EXPECT_TRUE(plan.fipr);
  EXPECT_TRUE(plan.has_cells());
  EXPECT_EQ(plan.units(), 8);
  ASSERT_EQ(plan.unit_cells.size(), 4u);
  EXPECT_EQ(plan.unit_cells[0].method, BenchMethod::gt);
  EXPECT_EQ(plan.unit_cells[1].method, BenchMethod::ipr);
  EXPECT_EQ(plan.unit_cells[3].method, BenchMethod::fipr);
  EXPECT_EQ(plan.variant_of(plan.unit_cells[3]).refresh, 2);
  const SweepLayout layout = sweep_layout(plan);
  EXPECT_EQ(layout.units(), 8);
  ASSERT_EQ(layout.unit_cells.size(), 4u);
  EXPECT_EQ(layout.unit_cells[2].refresh, 1);
  EXPECT_EQ(layout.unit_cells[2].fovea_deg, 7.5);
  EXPECT_NE(sweep_command(plan).find("--methods gt,ipr,fipr --refresh 1,2 --fovea-deg 7.5"), std::string::npos)
      << sweep_command(plan);
  EXPECT_NE(cell_command(plan, "columns", 9.0f, 4, plan.unit_cells[3]).find("--scenes columns --spp 4"),
            std::string::npos);
}

}  // namespace
}  // namespace fovlab::bench
