#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "analysis/report/svg_chart.h"
#include "analysis/report/svg_drawing.h"

namespace fovlab::analysis {

using namespace svg_detail;

std::string render_histogram_svg(const Histogram& histogram) {
  // Each usable value with its weight (1, or its entry of `counts`).
  std::vector<double> values;
  std::vector<double> weights;
  const bool weighted = histogram.counts.size() == histogram.values.size();
  for (std::size_t i = 0; i < histogram.values.size(); ++i) {
    if (!usable(histogram.values[i])) continue;
    double weight = weighted ? histogram.counts[i] : 1.0;
    if (!usable(weight) || weight < 0.0) weight = 0.0;
    values.push_back(histogram.values[i]);
    weights.push_back(std::round(weight));
  }
  std::vector<double> edges;
  for (double edge : histogram.bin_edges) {
    if (usable(edge)) edges.push_back(edge);
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  if (edges.size() < 2) {  // no usable bins: one bin over the data (or [0, 1])
    Extent extent;
    for (double value : values) extent.add(value);
    if (extent.empty()) extent = {0.0, 1.0};
    if (!(extent.hi > extent.lo)) extent = {extent.lo - 0.5, extent.hi + 0.5};
    edges = {extent.lo, extent.hi};
  }
  std::vector<uint64_t> counts(edges.size() - 1, 0);
  for (std::size_t v = 0; v < values.size(); ++v) {
    // Values below the first edge count in the first bin, at or above the last edge in the last.
    const auto upper = std::upper_bound(edges.begin(), edges.end(), values[v]);
    std::size_t bin = upper == edges.begin() ? 0 : static_cast<std::size_t>(upper - edges.begin()) - 1;
    bin = std::min(bin, counts.size() - 1);
    counts[bin] += static_cast<uint64_t>(weights[v]);
  }
  const uint64_t most = counts.empty() ? 0 : *std::max_element(counts.begin(), counts.end());

  Frame frame;
  Extent x_extent;
  x_extent.add(edges.front());
  x_extent.add(edges.back());
  Extent y_extent;
  y_extent.add(0.0);
  y_extent.add(static_cast<double>(std::max<uint64_t>(most, 1)));
  frame.x = make_axis(x_extent, std::nullopt, std::nullopt, false);
  frame.y = make_axis(y_extent, 0.0, std::nullopt, true);

  std::string out = svg_open(histogram.title);
  out += draw_axes(frame, histogram.x_label, "count");
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (counts[i] == 0) continue;
    const double x1 = frame.px(edges[i]);
    const double x2 = frame.px(edges[i + 1]);
    const double y = frame.py(static_cast<double>(counts[i]));
    out += "<rect" + attr("x", x1) + attr("y", y) + attr("width", std::max(x2 - x1, 0.5)) +
           attr("height", frame.py(0.0) - y) + " fill=\"" + kPalette[0] +
           "\" stroke=\"#ffffff\" stroke-width=\"1\"/>\n";
    // Without count labels, a bar too short to see (under 3 px) still gets its count: a rare late
    // frame must not vanish beside a tall bar.
    if (histogram.count_labels || frame.py(0.0) - y < 3.0)
      out += text_at((x1 + x2) / 2, y - 4, std::to_string(counts[i]), "middle", " font-size=\"11\"");
  }
  bool marked = false;
  for (double line : histogram.vertical_lines) {
    if (!usable(line) || line < frame.x.lo || line > frame.x.hi) continue;
    marked = true;
    out += "<line" + attr("x1", frame.px(line)) + attr("y1", frame.top) + attr("x2", frame.px(line)) +
           attr("y2", frame.bottom) + " stroke=\"" + kPalette[1] + "\" stroke-width=\"2\" stroke-dasharray=\"4 3\"/>\n";
  }
  if (marked && !histogram.vertical_lines_label.empty())
    out += text_at(frame.right - 4, frame.top + 14, histogram.vertical_lines_label, "end",
                   (std::string(" font-size=\"11\" fill=\"") + kPalette[1] + "\"").c_str());
  if (values.empty()) out += no_data_note(frame);
  out += "</svg>\n";
  return out;
}

}  // namespace fovlab::analysis
