#include "analysis/report/svg_chart.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <limits>
#include <regex>
#include <string>
#include <vector>

namespace fovlab::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Well-formedness without an XML parser: every '<' opens a tag, start and end tags nest, exactly one
// root element (svg), attribute quotes are balanced, and every '&' starts one of the five named
// entities.
testing::AssertionResult well_formed_svg(const std::string& svg) {
  std::vector<std::string> open;
  int roots = 0;
  std::size_t i = 0;
  while (i < svg.size()) {
    if (svg[i] == '&') {
      static const char* const kEntities[] = {"&amp;", "&lt;", "&gt;", "&quot;", "&apos;"};
      const bool known = std::any_of(std::begin(kEntities), std::end(kEntities),
                                     [&](const char* e) { return svg.compare(i, std::string(e).size(), e) == 0; });
      if (!known) return testing::AssertionFailure() << "bare '&' at " << i;
      ++i;
      continue;
    }
    if (svg[i] == '>') return testing::AssertionFailure() << "stray '>' at " << i;
    if (svg[i] != '<') {
      if (open.empty() && !std::isspace(static_cast<unsigned char>(svg[i]))) {
        return testing::AssertionFailure() << "text outside the root at " << i;
      }
      ++i;
      continue;
    }
    const std::size_t end = svg.find('>', i);
    if (end == std::string::npos) return testing::AssertionFailure() << "unterminated tag at " << i;
    const std::string tag = svg.substr(i + 1, end - i - 1);
    if (std::count(tag.begin(), tag.end(), '"') % 2 != 0)
      return testing::AssertionFailure() << "odd quotes in <" << tag;
    if (tag.find('<') != std::string::npos) return testing::AssertionFailure() << "'<' inside <" << tag;
    if (!tag.empty() && tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (open.empty() || open.back() != name) {
        return testing::AssertionFailure() << "</" << name << "> closes " << (open.empty() ? "nothing" : open.back());
      }
      open.pop_back();
    } else {
      const std::size_t name_end = tag.find_first_of(" \n/");
      const std::string name = tag.substr(0, name_end);
      if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) {
        return testing::AssertionFailure() << "bad tag <" << tag;
      }
      if (open.empty()) {
        ++roots;
        if (name != "svg") return testing::AssertionFailure() << "root element is " << name;
      }
      if (tag.back() != '/') open.push_back(name);
    }
    i = end + 1;
  }
  if (!open.empty()) return testing::AssertionFailure() << "<" << open.back() << "> never closed";
  if (roots != 1) return testing::AssertionFailure() << roots << " root elements";
  return testing::AssertionSuccess();
}

testing::AssertionResult no_non_finite_text(const std::string& svg) {
  std::string lower = svg;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* word : {"nan", "inf"}) {
    const auto at = lower.find(word);
    if (at != std::string::npos) {
      return testing::AssertionFailure() << "'" << word << "' in: " << svg.substr(at > 40 ? at - 40 : 0, 80);
    }
  }
  return testing::AssertionSuccess();
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Tick labels as the renderer places them: x ticks centred 18 px under the plot (y = 380), y ticks
// right-aligned 8 px left of it (x = 64).
std::vector<double> x_ticks(const std::string& svg) {
  static const std::regex pattern(R"(<text x="[-0-9.]+" y="380\.00" text-anchor="middle">([^<]*)</text>)");
  std::vector<double> ticks;
  for (std::sregex_iterator it(svg.begin(), svg.end(), pattern), end; it != end; ++it) {
    ticks.push_back(std::stod((*it)[1].str()));
  }
  return ticks;
}

std::vector<double> y_ticks(const std::string& svg) {
  static const std::regex pattern(R"(<text x="64\.00" y="[-0-9.]+" text-anchor="end">([^<]*)</text>)");
  std::vector<double> ticks;
  for (std::sregex_iterator it(svg.begin(), svg.end(), pattern), end; it != end; ++it) {
    ticks.push_back(std::stod((*it)[1].str()));
  }
  return ticks;
}

// Ascending, evenly spaced by 1, 2 or 5 times a power of ten, and spanning [lo, hi].
testing::AssertionResult nice_ticks_covering(const std::vector<double>& ticks, double lo, double hi) {
  if (ticks.size() < 3 || ticks.size() > 12) return testing::AssertionFailure() << ticks.size() << " ticks";
  const double step = ticks[1] - ticks[0];
  if (!(step > 0)) return testing::AssertionFailure() << "step " << step;
  for (std::size_t i = 1; i < ticks.size(); ++i) {
    if (std::fabs(ticks[i] - ticks[i - 1] - step) > step * 1e-6) {
      return testing::AssertionFailure() << "uneven ticks at " << ticks[i];
    }
  }
  const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
  if (std::fabs(mantissa - 1) > 1e-6 && std::fabs(mantissa - 2) > 1e-6 && std::fabs(mantissa - 5) > 1e-6) {
    return testing::AssertionFailure() << "step " << step << " is not 1, 2 or 5 x 10^k";
  }
  if (ticks.front() > lo || ticks.back() < hi) {
    return testing::AssertionFailure() << "ticks " << ticks.front() << ".." << ticks.back() << " miss " << lo << ".."
                                       << hi;
  }
  return testing::AssertionSuccess();
}

XyChart sample_chart() {
  XyChart chart;
  chart.title = "Share per level";
  chart.x_label = "foveal_deg";
  chart.y_label = "share";
  XySeries points;
  points.label = "park";
  points.x = {5, 10, 20, 30};
  points.y = {0.2, 0.45, 0.7, 0.9};
  points.y_lower = {0.1, 0.3, 0.55, 0.8};
  points.y_upper = {0.35, 0.6, 0.82, 0.97};
  XySeries line;
  line.label = "logistic";
  line.style = XySeries::Style::line;
  for (int i = 0; i <= 50; ++i) {
    line.x.push_back(5 + 25.0 * i / 50);
    line.y.push_back(1 / (1 + std::exp(-(line.x.back() - 15) / 4)));
  }
  chart.series = {points, line};
  chart.bands = {{"threshold CI", 12, 17}};
  chart.horizontal_lines = {0.5};
  return chart;
}

TEST(XmlEscape, EscapesTheFiveSpecialCharactersAndDropsControlCharacters) {
  EXPECT_EQ(xml_escape("a < b & c > \"d\" 'e'"), "a &lt; b &amp; c &gt; &quot;d&quot; &apos;e&apos;");
  EXPECT_EQ(xml_escape(std::string("x\x01y\tz\n", 6)), "x y\tz\n");
  EXPECT_EQ(xml_escape("caf\xC3\xA9"), "caf\xC3\xA9");
  EXPECT_EQ(xml_escape(""), "");
}

TEST(XyChart, IsOneWellFormedSvgDocumentWithEveryPart) {
  const std::string svg = render_xy_chart_svg(sample_chart());
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_TRUE(no_non_finite_text(svg));
  EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 720 420\"", 0), 0u);
  EXPECT_EQ(count(svg, "<svg"), 1u);
  EXPECT_NE(svg.find(">Share per level</text>"), std::string::npos);
  EXPECT_NE(svg.find(">foveal_deg</text>"), std::string::npos);
  EXPECT_NE(svg.find(">share</text>"), std::string::npos);
  EXPECT_NE(svg.find(">park</text>"), std::string::npos);  // legend
  EXPECT_NE(svg.find(">logistic</text>"), std::string::npos);
  EXPECT_NE(svg.find(">threshold CI</text>"), std::string::npos);
  EXPECT_EQ(count(svg, "stroke-dasharray"), 1u);      // the line at 0.5
  EXPECT_EQ(count(svg, "<polyline"), 1u);             // the curve
  EXPECT_EQ(count(svg, "<circle"), 4u + 1u);          // 4 points + legend marker
  EXPECT_EQ(count(svg, "fill-opacity=\"0.3\""), 2u);  // band + legend swatch
  // Error bars: one group of three lines a point.
  EXPECT_EQ(count(svg, "stroke-width=\"1.2\"><line"), 4u);
}

TEST(XyChart, EscapesEveryText) {
  XyChart chart = sample_chart();
  chart.title = "a < b & \"c\"";
  chart.x_label = "x <i>";
  chart.y_label = "y's";
  chart.series[0].label = "park & <ride>";
  const std::string svg = render_xy_chart_svg(chart);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_NE(svg.find("a &lt; b &amp; &quot;c&quot;"), std::string::npos);
  EXPECT_NE(svg.find("x &lt;i&gt;"), std::string::npos);
  EXPECT_NE(svg.find("y&apos;s"), std::string::npos);
  EXPECT_NE(svg.find("park &amp; &lt;ride&gt;"), std::string::npos);
  EXPECT_EQ(svg.find("<i>"), std::string::npos);
  EXPECT_EQ(svg.find("<ride>"), std::string::npos);
}

TEST(XyChart, TicksAreNiceAndCoverTheData) {
  struct Case {
    double x0, x1, y0, y1;
  };
  for (const Case& c : {Case{3.7, 42.1, -0.013, 0.021}, Case{0, 1, 1e6, 1e6 + 3}, Case{-250, 7, 0.5, 0.51},
                        Case{1e-7, 9e-7, -3e5, 8e5}}) {
    XyChart chart;
    XySeries series;
    series.x = {c.x0, (c.x0 + c.x1) / 2, c.x1};
    series.y = {c.y1, c.y0, (c.y0 + c.y1) / 2};
    chart.series = {series};
    const std::string svg = render_xy_chart_svg(chart);
    SCOPED_TRACE(svg);
    EXPECT_TRUE(well_formed_svg(svg));
    EXPECT_TRUE(no_non_finite_text(svg));
    EXPECT_TRUE(nice_ticks_covering(x_ticks(svg), c.x0, c.x1));
    EXPECT_TRUE(nice_ticks_covering(y_ticks(svg), c.y0, c.y1));
  }
}

TEST(XyChart, ErrorBarsAndBandsWidenTheAxes) {
  XyChart chart;
  XySeries series;
  series.x = {1, 2};
  series.y = {0.5, 0.6};
  series.y_lower = {-0.7, 0.4};
  series.y_upper = {0.6, 1.9};
  chart.series = {series};
  chart.bands = {{"", -4, 0}};
  chart.horizontal_lines = {2.4};
  const std::string svg = render_xy_chart_svg(chart);
  EXPECT_TRUE(nice_ticks_covering(x_ticks(svg), -4, 2));
  EXPECT_TRUE(nice_ticks_covering(y_ticks(svg), -0.7, 2.4));
}

TEST(XyChart, FixedRangeGivesTicksInsideIt) {
  XyChart chart = sample_chart();
  chart.y_min = 0.0;
  chart.y_max = 1.0;
  const std::string svg = render_xy_chart_svg(chart);
  EXPECT_EQ(y_ticks(svg), (std::vector<double>{0, 0.2, 0.4, 0.6, 0.8, 1}));
  EXPECT_NE(svg.find(">0.6</text>"), std::string::npos);  // not 0.6000000000000001
}

TEST(XyChart, PointsOutsideAFixedRangeAreLeftOut) {
  XyChart chart;
  XySeries series;
  series.x = {1, 2, 3};
  series.y = {0.5, 1.5, -0.5};
  chart.series = {series};
  chart.y_min = 0.0;
  chart.y_max = 1.0;
  const std::string svg = render_xy_chart_svg(chart);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_EQ(count(svg, "<circle"), 1u);
}

TEST(XyChart, DegenerateInputsGiveAValidChart) {
  std::vector<XyChart> charts;
  charts.emplace_back();  // nothing at all
  {
    XyChart empty_series;
    empty_series.series.resize(2);
    empty_series.series[1].style = XySeries::Style::line;
    charts.push_back(empty_series);
  }
  {
    XyChart single;
    XySeries s;
    s.label = "one";
    s.x = {7};
    s.y = {0.25};
    single.series = {s};
    charts.push_back(single);
  }
  {
    XyChart equal;
    XySeries s;
    s.x = {5, 5, 5};
    s.y = {2, 2, 2};
    equal.series = {s};
    charts.push_back(equal);
  }
  {
    XyChart zero;
    XySeries s;
    s.x = {0, 0};
    s.y = {0, 0};
    s.style = XySeries::Style::bars;
    zero.series = {s};
    charts.push_back(zero);
  }
  {
    XyChart bad;
    XySeries s;
    s.x = {kNaN, 1, 2, kInf, 1e308};
    s.y = {1, kNaN, -kInf, 3, 4};
    s.y_lower = {kNaN, kNaN};  // wrong length: ignored
    bad.series = {s};
    bad.bands = {{"nothing", kNaN, 1}};
    bad.horizontal_lines = {kNaN, kInf};
    bad.x_min = kNaN;
    bad.y_max = -kInf;
    charts.push_back(bad);
  }
  {
    XyChart reversed;
    XySeries s;
    s.x = {1, 2};
    s.y = {1, 2};
    reversed.series = {s};
    reversed.x_min = 10.0;
    reversed.x_max = 0.0;
    reversed.y_min = 3.0;
    reversed.y_max = 3.0;
    charts.push_back(reversed);
  }
  for (std::size_t i = 0; i < charts.size(); ++i) {
    const std::string svg = render_xy_chart_svg(charts[i]);
    SCOPED_TRACE("chart " + std::to_string(i) + "\n" + svg);
    EXPECT_TRUE(well_formed_svg(svg));
    EXPECT_TRUE(no_non_finite_text(svg));
    const std::vector<double> xs = x_ticks(svg);
    const std::vector<double> ys = y_ticks(svg);
    ASSERT_GE(xs.size(), 2u);
    ASSERT_GE(ys.size(), 2u);
    EXPECT_LT(xs.front(), xs.back());
    EXPECT_LT(ys.front(), ys.back());
  }
  EXPECT_NE(render_xy_chart_svg(charts[0]).find(">no data</text>"), std::string::npos);
  EXPECT_EQ(count(render_xy_chart_svg(charts[2]), "<circle"), 2u);  // the point + its legend marker
  const std::string equal = render_xy_chart_svg(charts[3]);
  EXPECT_TRUE(nice_ticks_covering(x_ticks(equal), 5, 5));
  EXPECT_TRUE(nice_ticks_covering(y_ticks(equal), 2, 2));
  EXPECT_EQ(count(render_xy_chart_svg(charts[5]), "<circle"), 0u);  // no point has both coordinates usable
}

TEST(XyChart, LinesBreakAtMissingValues) {
  XyChart chart;
  XySeries line;
  line.style = XySeries::Style::line;
  line.x = {0, 1, 2, 3, 4, 5, 6};
  line.y = {0, 1, kNaN, 3, 4, kInf, 6};
  chart.series = {line};
  const std::string svg = render_xy_chart_svg(chart);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_EQ(count(svg, "<polyline"), 2u);  // 0-1 and 3-4
  EXPECT_EQ(count(svg, "<circle"), 1u);    // the lone point 6
}

TEST(XyChart, GroupedBarsStartAtZero) {
  XyChart chart;
  XySeries a;
  a.style = XySeries::Style::bars;
  a.label = "a";
  a.x = {1, 2, 3};
  a.y = {4, 5, 6};
  XySeries b = a;
  b.label = "b";
  b.y = {1, 2, 3};
  b.y_lower = {0.5, 1.5, 2.5};
  b.y_upper = {1.5, 2.5, 3.5};
  chart.series = {a, b};
  const std::string svg = render_xy_chart_svg(chart);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_EQ(count(svg, "fill=\"#0072B2\"/>"), 3u + 1u);  // bars of a + legend swatch
  EXPECT_EQ(count(svg, "fill=\"#D55E00\"/>"), 3u + 1u);
  EXPECT_EQ(y_ticks(svg).front(), 0.0);
  EXPECT_TRUE(nice_ticks_covering(x_ticks(svg), 0.6, 3.4));  // the outer bar edges
}

TEST(XyChart, ManySeriesCycleColoursAndKeepTheLegendInside) {
  XyChart chart;
  for (int i = 0; i < 40; ++i) {
    XySeries s;
    s.label = "series number " + std::to_string(i) + " with a rather long label indeed";
    s.x = {double(i)};
    s.y = {double(i % 7)};
    chart.series.push_back(s);
  }
  const std::string svg = render_xy_chart_svg(chart);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_NE(svg.find(" more</text>"), std::string::npos);
  EXPECT_EQ(svg.find("#F0E442"), std::string::npos);       // yellow is never a series colour
  EXPECT_NE(svg.find("\xE2\x80\xA6"), std::string::npos);  // long labels are cut
}

TEST(XyChart, SameInputSameBytes) {
  const XyChart chart = sample_chart();
  EXPECT_EQ(render_xy_chart_svg(chart), render_xy_chart_svg(chart));
  XyChart other = chart;
  other.series[0].y[0] = 0.21;
  EXPECT_NE(render_xy_chart_svg(chart), render_xy_chart_svg(other));
}

std::vector<int> bar_counts(const std::string& svg) {
  static const std::regex pattern(R"(font-size="11">([0-9]+)</text>)");
  std::vector<int> counts;
  for (std::sregex_iterator it(svg.begin(), svg.end(), pattern), end; it != end; ++it) {
    counts.push_back(std::stoi((*it)[1].str()));
  }
  return counts;
}

TEST(HistogramSvg, CountsPerBinWithEndBinsTakingOutliers) {
  Histogram histogram;
  histogram.title = "Thresholds";
  histogram.x_label = "foveal_deg";
  histogram.values = {0.5, 1.5, 1.6, 2.5, 2.5, 2.5, -10, 100, kNaN, kInf, 3.0};
  histogram.bin_edges = {0, 1, 2, 3};
  const std::string svg = render_histogram_svg(histogram);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_TRUE(no_non_finite_text(svg));
  EXPECT_EQ(bar_counts(svg), (std::vector<int>{2, 2, 5}));  // 3.0 (the last edge) and 100 in the last bin
  const std::vector<double> ys = y_ticks(svg);
  ASSERT_FALSE(ys.empty());
  EXPECT_EQ(ys.front(), 0.0);
  EXPECT_GE(ys.back(), 5.0);
  for (double tick : ys) EXPECT_EQ(tick, std::round(tick)) << "count ticks are whole numbers";
  EXPECT_TRUE(nice_ticks_covering(x_ticks(svg), 0, 3));
  EXPECT_NE(svg.find(">count</text>"), std::string::npos);
}

TEST(HistogramSvg, OneValueGivesIntegerTicks) {
  Histogram histogram;
  histogram.values = {10};
  histogram.bin_edges = {7.5, 12.5, 17.5};
  const std::string svg = render_histogram_svg(histogram);
  EXPECT_EQ(bar_counts(svg), (std::vector<int>{1}));
  const std::vector<double> ys = y_ticks(svg);
  EXPECT_EQ(ys, (std::vector<double>{0, 1}));
}

TEST(HistogramSvg, DegenerateInputsGiveAValidChart) {
  std::vector<Histogram> histograms(5);
  histograms[1].values = {4, 4, 4};  // no edges, one value
  histograms[2].values = {1, 2, 3};
  histograms[2].bin_edges = {3, 1, 2, 2, kNaN};  // unsorted, repeated, NaN
  histograms[3].bin_edges = {1, 2};              // no values
  histograms[4].values = {kNaN, -kInf};
  histograms[4].bin_edges = {kInf};
  for (std::size_t i = 0; i < histograms.size(); ++i) {
    const std::string svg = render_histogram_svg(histograms[i]);
    SCOPED_TRACE("histogram " + std::to_string(i) + "\n" + svg);
    EXPECT_TRUE(well_formed_svg(svg));
    EXPECT_TRUE(no_non_finite_text(svg));
    EXPECT_GE(x_ticks(svg).size(), 2u);
  }
  EXPECT_EQ(bar_counts(render_histogram_svg(histograms[1])), (std::vector<int>{3}));
  EXPECT_EQ(bar_counts(render_histogram_svg(histograms[2])), (std::vector<int>{1, 2}));
  EXPECT_NE(render_histogram_svg(histograms[0]).find(">no data</text>"), std::string::npos);
}

TEST(HeatMapSvg, CellsCarryTheirValueAndAViridisColour) {
  HeatMap map;
  map.title = "SSIM <by> level";
  map.x_label = "level";
  map.y_label = "eccentricity";
  map.x_values = {1, 2, 3};
  map.y_values = {10, 20};
  map.cells = {0.25, 0.5, kNaN, 0.75, 1.0, 0.5};
  map.cell_format = "%.1f%%";
  const std::string svg = render_heat_map_svg(map);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_TRUE(no_non_finite_text(svg));
  EXPECT_NE(svg.find("SSIM &lt;by&gt; level"), std::string::npos);
  for (const char* text : {">0.2%</text>", ">0.5%</text>", ">0.8%</text>", ">1.0%</text>"}) {
    EXPECT_NE(svg.find(text), std::string::npos) << text;
  }
  EXPECT_EQ(count(svg, "%</text>"), 5u);  // the NaN cell has no text
  EXPECT_EQ(count(svg, "fill=\"#dddddd\""), 1u);
  EXPECT_NE(svg.find("fill=\"#440154\""), std::string::npos);  // the smallest value: viridis' dark end
  EXPECT_NE(svg.find("fill=\"#fde725\""), std::string::npos);  // the largest: its yellow end
  for (const char* label : {">1</text>", ">2</text>", ">3</text>", ">10</text>", ">20</text>"}) {
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  }
}

TEST(HeatMapSvg, BadFormatsAndShapesAreSafe) {
  HeatMap map;
  map.x_values = {1, 2};
  map.y_values = {1};
  map.cells = {3.14159};  // one short: the missing cell is blank
  for (const char* format : {"%s", "%d", "%.2f %.2f", "%n", "%999.999f", "no conversion", "%.3lf"}) {
    map.cell_format = format;
    const std::string svg = render_heat_map_svg(map);
    SCOPED_TRACE(format);
    EXPECT_TRUE(well_formed_svg(svg));
    EXPECT_TRUE(no_non_finite_text(svg));
    EXPECT_NE(svg.find(">3.14</text>"), std::string::npos);  // the default "%.2f"
  }
  HeatMap empty;
  EXPECT_TRUE(well_formed_svg(render_heat_map_svg(empty)));
  HeatMap equal;
  equal.x_values = {kNaN, 1};
  equal.y_values = {0};
  equal.cells = {2, 2, 99};  // one too many: ignored
  const std::string svg = render_heat_map_svg(equal);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_TRUE(no_non_finite_text(svg));
  EXPECT_EQ(count(svg, ">2.00</text>"), 2u);
  EXPECT_EQ(svg.find(">99.00</text>"), std::string::npos);
  EXPECT_EQ(render_heat_map_svg(equal), svg);
}

TEST(HeatMapSvg, AFixedColourScaleAndMarkedCells) {
  HeatMap map;
  map.x_values = {0.05, 0.3};
  map.y_values = {0.3, 0.8};
  map.cells = {2.0, 2.5, 1.5, 2.0};
  const std::string plain = render_heat_map_svg(map);
  map.colour_min = 1.0;
  map.colour_max = 3.0;
  map.marked_cells = {1, 99};  // 99 is outside the grid: ignored
  map.marked_label = "outlined: best";
  const std::string svg = render_heat_map_svg(map);
  EXPECT_TRUE(well_formed_svg(svg));
  // On the scale 1..3 the largest value (2.5) is not the yellow end nor the smallest (1.5) the dark end.
  EXPECT_NE(plain.find("fill=\"#fde725\""), std::string::npos);
  EXPECT_EQ(count(svg, "fill=\"#fde725\" stroke"), 0u);
  EXPECT_EQ(count(svg, "fill=\"#440154\" stroke"), 0u);
  // The two cells at 2.0 (the middle of 1..3) share viridis' middle colour.
  EXPECT_EQ(count(svg, "fill=\"#21908d\" stroke"), 2u);
  for (const char* tick : {">1</text>", ">3</text>"}) EXPECT_NE(svg.find(tick), std::string::npos) << tick;
  EXPECT_EQ(count(svg, "fill=\"none\" stroke=\"#000000\" stroke-width=\"3\""), 1u);
  EXPECT_NE(svg.find(">outlined: best</text>"), std::string::npos);
  EXPECT_EQ(plain.find("stroke-width=\"3\""), std::string::npos);
  // Bounds in the wrong order are ignored: the data's extent again.
  map.colour_min = 3.0;
  map.colour_max = 1.0;
  EXPECT_NE(render_heat_map_svg(map).find("fill=\"#fde725\""), std::string::npos);
}

TEST(XyChart, ColourOverridesSmallPointsAndVerticalLines) {
  XyChart chart;
  XySeries data{"blur: data", XySeries::Style::points, {1, 2}, {0.5, 0.5}, {}, {}, {}};
  data.colour = 1;  // the second colour and marker (square), whatever its index
  XySeries small{"each participant", XySeries::Style::points, {1, 2, 3}, {0.2, 0.4, 0.6}, {}, {}, {}};
  small.colour = 1;
  small.small = true;
  chart.series = {data, small};
  chart.bands = {{"", 1.5, 2.5, std::size_t{1}}};
  chart.vertical_lines = {{"blur: headline 2", 2.0, std::size_t{1}}, {"", 9.0, std::nullopt}};
  const std::string svg = render_xy_chart_svg(chart);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_EQ(count(svg, "<circle"), 0u) << "colour 1 draws squares";
  EXPECT_EQ(count(svg, "fill=\"#D55E00\" fill-opacity=\"0.5\""), 3u + 1u);  // the small points and their legend sample
  EXPECT_EQ(count(svg, "fill=\"#D55E00\" fill-opacity=\"0.18\""), 1u);      // the band, in the series colour
  // Both lines drawn (the one at 9 widens the axis), one with a legend entry (line and sample).
  EXPECT_EQ(count(svg, "stroke-dasharray=\"4 3\""), 3u);
  EXPECT_NE(svg.find(">blur: headline 2</text>"), std::string::npos);
  EXPECT_NE(svg.find(">10</text>"), std::string::npos) << "the x axis reaches the line at 9";
}

TEST(Histogram, CountsTalliedValuesAndLabelsBarsTooShortToSee) {
  Histogram histogram;
  histogram.values = {16.0, 17.0, 40.0};
  histogram.counts = {600.0, 400.0, 1.0};  // 1000 intervals near 16 ms, one late
  histogram.bin_edges = {0, 20, 30, 50};
  histogram.count_labels = false;
  histogram.vertical_lines = {25.0};
  histogram.vertical_lines_label = "late beyond 25 ms";
  const std::string svg = render_histogram_svg(histogram);
  EXPECT_TRUE(well_formed_svg(svg));
  EXPECT_EQ(count(svg, "font-size=\"11\">1</text>"), 1u) << "the one late interval is labelled";
  EXPECT_EQ(count(svg, "font-size=\"11\">1000</text>"), 0u) << "the tall bar is not";
  EXPECT_NE(svg.find(">late beyond 25 ms</text>"), std::string::npos);
  EXPECT_EQ(count(svg, "stroke-dasharray=\"4 3\""), 1u);
  // Counts that do not match the values are ignored (each value counts once).
  histogram.counts = {5.0};
  histogram.count_labels = true;
  const std::string plain = render_histogram_svg(histogram);
  EXPECT_EQ(count(plain, "font-size=\"11\">1</text>"), 1u);  // 40 ms alone in its bin
  EXPECT_EQ(count(plain, "font-size=\"11\">2</text>"), 1u);  // 16 and 17 ms
}

}  // namespace
}  // namespace fovlab::analysis
