// The Pareto front of fovlab bench (bench/bench_pareto): which cells no other cell beats in both speed
// and error, and the chart that marks them.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "bench/bench_pareto.h"

namespace {

using fovlab::bench::cell_label;
using fovlab::bench::ChartCell;
using fovlab::bench::pareto_chart_svg;
using fovlab::bench::pareto_front;
using fovlab::bench::TradeOff;

TEST(BenchPareto, FrontKeepsThePointsNothingBeatsInBoth) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<TradeOff> points = {
      {1.0, 0.0},   // GT: slowest, exact
      {2.0, 0.10},  // beaten by {3.0, 0.05}
      {1.5, 0.20},  // beaten by both of the above
      {3.0, 0.05},  // front
      {3.0, 0.05},  // the same again: equal points do not dominate each other
      {8.0, 0.30},  // fastest: front
      {8.0, 0.31},  // as fast, more error: beaten
      {nan, 0.0},   // not a measurement: never on the front, beats nothing
      {9.0, nan},
  };
  const std::vector<bool> expected = {true, false, false, true, true, true, false, false, false};
  EXPECT_EQ(pareto_front(points), expected);
  EXPECT_TRUE(pareto_front({}).empty());
  EXPECT_EQ(pareto_front({{1.0, 0.0}}), std::vector<bool>{true});
}

TEST(BenchPareto, ChartLabelsEveryCellAndMarksTheFront) {
  std::vector<ChartCell> cells;
  cells.push_back({"gt", 1, 1, 0.0, {1.0, 0.0}, true});
  cells.push_back({"gt", 4, 1, 0.0, {1.0, 0.0}, true});
  cells.push_back({"ipr", 4, 1, 0.0, {1.8, 0.001}, true});
  cells.push_back({"fipr", 4, 2, 7.5, {5.0, 0.04}, true});
  cells.push_back({"fipr", 16, 4, 12.5, {4.0, 0.05}, false});
  EXPECT_EQ(cell_label(cells[3]), "4/2/7.5");
  EXPECT_EQ(cell_label(cells[4]), "16/4/12.5");
  EXPECT_EQ(cell_label(cells[2]), "ipr 4");
  EXPECT_EQ(cell_label(cells[0]), "gt");
  // A sampling model's label carries its shaded samples over RMFR's when the cell has them.
  ChartCell kfr{"kfr", 1, 1, 0.0, {1.2, 0.02}, false};
  EXPECT_EQ(cell_label(kfr), "kfr 1");
  kfr.shaded_over_reference = 0.8734;
  EXPECT_EQ(cell_label(kfr), "kfr 1 (0.873x rmfr's samples)");

  const std::string svg = pareto_chart_svg("primitives <test>", "FLIP against GT", cells);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("primitives &lt;test&gt;"), std::string::npos);
  for (const char* label : {">4/2/7.5</text>", ">16/4/12.5</text>", ">ipr 4</text>", ">gt</text>"}) {
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  }
  EXPECT_NE(svg.find(">gt</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">gt</text>"), svg.rfind(">gt</text>"));  // GT's cells coincide: drawn once
  EXPECT_NE(svg.find("Pareto front (not dominated)"), std::string::npos);
  EXPECT_NE(svg.find("<polyline"), std::string::npos);  // the front, connected
  EXPECT_NE(svg.find("FIPR 16 spp"), std::string::npos);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
}

}  // namespace
