#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/report/report_formats.h"
#include "analysis/report/svg_chart.h"
#include "core/number_text.h"

namespace fovlab::analysis::report_detail {
namespace {

// "2 / 3; 0.42 (0.61) deg, 0.05 deg": passed / attempts, then over the passed ones the mean accuracy
// (its worst) and the mean precision; "none" when the study validated nothing.
std::string validation_text(const ValidationSummary& validation) {
  if (validation.attempts == 0) return "none";
  std::string text = std::to_string(validation.passed) + " / " + std::to_string(validation.attempts);
  if (validation.passed > 0)
    text += "; " + html_number(validation.mean_accuracy_deg) + " (" + html_number(validation.worst_accuracy_deg) +
            ") deg, " + html_number(validation.mean_precision_deg) + " deg";
  return text;
}

// The test as one phrase: "exact binomial, two-sided, H0 p = 1/2, Holm across levels, alpha 0.05".
std::string test_description(const AnalysisResult& result) {
  const std::string sidedness = result.alternative == Alternative::two_sided
                                    ? std::string("two-sided")
                                    : "one-sided (" + std::string(alternative_name(result.alternative)) + ")";
  return "exact binomial, " + sidedness + ", H0 p = 1/2, Holm across levels, alpha " + format_number(result.alpha, 6);
}

std::string html_escape(const std::string& text) { return xml_escape(text); }

std::string html_row(const std::vector<std::string>& cells, bool header = false) {
  const char* tag = header ? "th" : "td";
  std::string row = "<tr>";
  for (const std::string& cell : cells) row += std::string("<") + tag + ">" + html_escape(cell) + "</" + tag + ">";
  return row + "</tr>\n";
}

std::string html_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  // In a box that scrolls sideways, so a wide table never runs off the page.
  std::string table = "<div class=\"table\"><table>\n<thead>" + html_row(header, true) + "</thead>\n<tbody>\n";
  for (const auto& row : rows) table += html_row(row);
  return table + "</tbody>\n</table></div>\n";
}

// The SVG document as an inline element: HTML needs no namespace declaration, and without it the
// page holds no URL at all.
std::string inline_svg(const std::string& svg) {
  std::string text = svg;
  const std::string xmlns = " xmlns=\"http://www.w3.org/2000/svg\"";
  const auto at = text.find(xmlns);
  if (at != std::string::npos) text.erase(at, xmlns.size());
  return text;
}

// A plot as a figure: the SVG inline, its caption naming its file.
std::string html_figure(const Plot& plot) {
  return "<figure>\n" + inline_svg(plot.svg) + "<figcaption>" + html_escape(plot.caption) + " (" +
         html_escape(plot.file_name) + ")</figcaption>\n</figure>\n";
}

constexpr const char* kStyle = R"(body{font-family:sans-serif;margin:2em auto;max-width:1100px;padding:0 1em;color:#222}
h1{font-size:1.6em}h2{font-size:1.25em;margin-top:2em;border-bottom:1px solid #ccc}
div.table{overflow-x:auto;max-width:100%}
table{border-collapse:collapse;margin:0.5em 0;font-size:0.85em}
th,td{border:1px solid #ccc;padding:0.25em 0.4em;text-align:left;vertical-align:top;max-width:24em}
th{background:#f0f0f0}tbody tr:nth-child(even){background:#fafafa}
dl{display:grid;grid-template-columns:max-content auto;gap:0.2em 1em}dt{font-weight:bold}dd{margin:0}
figure{margin:1em 0}figcaption{font-size:0.9em;color:#555;max-width:720px}
svg{max-width:100%;height:auto}
table.headline{font-size:1em}table.headline td.value{font-weight:bold;white-space:nowrap}
tr.not-estimable td{background:#fdecea}tr.biased td{background:#fff4e0}
span.status{font-weight:bold}p.definition{font-size:0.9em;color:#333}
details{margin:0.5em 0}
)";

// The papers a report can cite, by the name it cites them with; the full list, and what fovlab
// takes from each, is docs/references.md.
struct PaperReference {
  std::string_view cited_as;
  std::string_view reference;
};
constexpr PaperReference kPaperReferences[] = {
    {"Polychronakis et al. 2023",
     "A. Polychronakis, G. A. Koulieris and K. Mania. An Inverted Pyramid Acceleration Structure Guiding Foveated "
     "Sphere Tracing for Implicit Surfaces in VR. Eurographics, 2023."},
    {"Polychronakis et al. 2021",
     "A. Polychronakis, G. A. Koulieris and K. Mania. Emulating Foveated Path Tracing. Motion, Interaction and Games "
     "(MIG '21), ACM, 2021. doi:10.1145/3487983.3488295"},
    {"Ye et al. 2022",
     "G. Ye, A. Xie, S. Jabbireddy, Y. Li, X. Yang and X. Meng. Rectangular Mapping-based Foveated Rendering. IEEE "
     "Conference on Virtual Reality and 3D User Interfaces (IEEE VR), 2022."},
    {"Bruder et al. 2019",
     "V. Bruder, C. Schulz, R. Bauer, S. Frey, D. Weiskopf and T. Ertl. Voronoi-Based Foveated Volume Rendering. "
     "EuroVis 2019 Short Papers, Eurographics, 2019. doi:10.2312/evs.20191172"},
};

// A References section listing, in full, each paper that `html` cites by authors and year.
std::string html_references(const std::string& html) {
  std::string items;
  for (const PaperReference& paper : kPaperReferences)
    if (html.find(paper.cited_as) != std::string::npos)
      items += "<li><strong>" + std::string(paper.cited_as) +
               "</strong>: " + html_escape(std::string(paper.reference)) + "</li>\n";
  if (items.empty()) return {};
  return "<h2 id=\"references\">References</h2>\n<ul>\n" + items + "</ul>\n";
}

// The frame-interval section: the study's and each session's summary, the study's histogram and
// the sessions' (collapsed).
std::string html_frame_intervals(const AnalysisResult& result, const std::vector<Plot>& frame_plots) {
  std::string html = "<h2 id=\"frame-intervals\">Frame intervals</h2>\n";
  html +=
      "<p>The intervals between consecutive refreshes presented during each stimulus (the log's present times; "
      "the gap between two stimuli is not counted), over the complete trials, practice left out. Late: an "
      "interval beyond 1.5 refresh periods (a refresh missed). Median and p99 by nearest rank, SD the sample "
      "SD; intervals are rounded to the microsecond. The study row pools the included sessions. A headless "
      "session's presenter keeps a virtual clock, so its intervals are exact periods.</p>\n";
  const FrameIntervalSummary study = result.frame_intervals;
  int included = 0;
  for (const ParticipantRow& participant : result.participants) included += participant.excluded ? 0 : 1;
  auto row = [&](const std::string& name, const FrameIntervalSummary& frames) -> std::vector<std::string> {
    return {name,
            html_number(frames.refresh_hz),
            std::to_string(frames.intervals),
            html_number(frames.median_ms),
            html_number(frames.sd_ms),
            html_number(frames.p99_ms),
            html_number(frames.max_ms),
            frames.intervals ? std::to_string(frames.late) : "\xE2\x80\x93",
            frames.late_share ? format_number(100.0 * *frames.late_share, 3) + " %" : "\xE2\x80\x93"};
  };
  std::vector<std::vector<std::string>> rows;
  rows.push_back(row("study (" + std::to_string(included) + (included == 1 ? " session)" : " sessions)"), study));
  for (const ParticipantRow& participant : result.participants)
    rows.push_back(
        row(participant.participant + (participant.excluded ? " (excluded)" : ""), participant.frame_intervals));
  html += html_table({"session", "refresh (Hz)", "intervals", "median (ms)", "SD (ms)", "p99 (ms)", "max (ms)",
                      "late (> 1.5 refreshes)", "late share"},
                     rows);
  for (size_t i = 0; i < frame_plots.size(); ++i) {
    if (i == 1) html += "<details><summary>Each session's histogram</summary>\n";
    html += html_figure(frame_plots[i]);
  }
  if (frame_plots.size() > 1) html += "</details>\n";
  return html;
}

// "[-54, 49, 54, -56] deg, 0.44 x 0.44 px/deg": an eye's field of view and its pixels per degree
// at the view's centre (where a radian spans the image plane's unit length).
std::string eye_text(const std::optional<std::array<double, 4>>& fov_deg, const HeadsetSummary& headset) {
  if (!fov_deg) return "not recorded";
  const auto [left, right, up, down] = *fov_deg;
  const auto tan_deg = [](double degrees) { return std::tan(degrees * std::numbers::pi / 180.0); };
  const double per_degree = std::numbers::pi / 180.0;
  const double x_px_per_deg = headset.eye_width_px / (tan_deg(right) - tan_deg(left)) * per_degree;
  const double y_px_per_deg = headset.eye_height_px / (tan_deg(up) - tan_deg(down)) * per_degree;
  return "[" + format_number(left, 4) + ", " + format_number(right, 4) + ", " + format_number(up, 4) + ", " +
         format_number(down, 4) + "] deg, " + format_number(x_px_per_deg, 3) + " x " + format_number(y_px_per_deg, 3) +
         " px/deg";
}

// "1.25% (3 of 240)": a count of a headset session's gaze refreshes as a share of them.
std::string gaze_share_text(const HeadsetSummary& headset, int64_t refreshes) {
  const std::optional<double> share = gaze_refresh_share(headset, refreshes);
  if (!share) return "no refreshes";
  return format_number(100.0 * *share, 3) + "% (" + std::to_string(refreshes) + " of " +
         std::to_string(headset.gaze_refreshes) + ")";
}

// Each headset session's gaze quality, a row an eye: what the log marks for each eye's pixel
// (invalid_gaze, right_eye_invalid_gaze); a log before schema 13 marks the left eye's only, and the
// right eye's row then gives only what follows from the left's.
std::string html_headset_gaze(const AnalysisResult& result) {
  std::vector<std::vector<std::string>> rows;
  bool right_unmarked = false;
  for (const ParticipantRow& p : result.participants) {
    if (!p.headset) continue;
    const HeadsetSummary& headset = *p.headset;
    const std::string session = p.participant + (p.excluded ? " (excluded)" : "");
    const std::string latency = p.latency_recorded ? html_number(p.latency.median_ms) + " (both eyes)" : "not recorded";
    const auto eye_row = [&](size_t eye) -> std::vector<std::string> {
      const std::string name = eye == 0 ? "left" : "right";
      const int64_t invalid = headset.gaze_invalid_other[eye], off_image = headset.gaze_off_image[eye];
      return {session, name, gaze_share_text(headset, invalid), gaze_share_text(headset, off_image),
              gaze_share_text(headset, invalid + off_image), latency};
    };
    rows.push_back(eye_row(0));
    if (headset.right_eye_marked) {
      rows.push_back(eye_row(1));
    } else {
      right_unmarked = true;
      const std::string unusable = gaze_share_text(headset, headset.gaze_invalid_other[0] + headset.gaze_off_image[0]);
      rows.push_back({session, "right", gaze_share_text(headset, headset.gaze_invalid_other[0]), "not logged",
                      headset.gaze_refreshes > 0 ? "at least " + unusable : unusable, latency});
    }
  }
  if (rows.empty()) return {};
  std::string html =
      "<p>Gaze per eye, over the refreshes of the complete trials' stimuli: invalid is a refresh whose gaze sample "
      "was none, not tracked or not finite (one combined gaze ray, so both eyes alike); off the image is a "
      "refresh whose pixel fell outside that eye's image. Such a refresh is shown with the eye's last usable "
      "gaze. The session makes the right eye's pixel from the left eye's, so every refresh without a usable left "
      "pixel counts as one without a usable right pixel too, with the left's reason.";
  if (right_unmarked)
    html += " A log before schema 13 marks invalid gaze for the left eye only (invalid_gaze), so there the "
            "refreshes where only the right eye's pixel fell off its image are not known, and the right eye's "
            "share is a lower bound.";
  html += "</p>\n";
  html += html_table({"session", "eye", "gaze invalid (no sample, not tracked)", "gaze off the eye's image",
                      "invalid or off the image", "gaze-to-present ms, median"},
                     rows);
  return html;
}

// The headset section, for studies with headset sessions: each session's runtime and eyes beside
// the frame timing and gaze figures, which a headset gives once for both eyes.
std::string html_headset(const AnalysisResult& result) {
  std::vector<std::vector<std::string>> rows;
  for (const ParticipantRow& p : result.participants) {
    if (!p.headset) continue;
    const HeadsetSummary& headset = *p.headset;
    const FrameIntervalSummary& frames = p.frame_intervals;
    rows.push_back(
        {p.participant + (p.excluded ? " (excluded)" : ""), headset.runtime,
         std::to_string(headset.eye_width_px) + " x " + std::to_string(headset.eye_height_px),
         eye_text(headset.fov_deg[0], headset), eye_text(headset.fov_deg[1], headset), headset.view_model,
         headset.gaze_fixation +
             (headset.fixation_distance_mm ? " (" + format_number(*headset.fixation_distance_mm, 6) + " mm)" : ""),
         p.present_clock.empty() ? "not recorded" : p.present_clock,
         std::to_string(frames.intervals) + ", median " + html_number(frames.median_ms) + " ms, " +
             std::to_string(frames.late) + " late",
         std::to_string(p.dropped_frames),
         headset.late_frames ? std::to_string(*headset.late_frames) : "not measured",
         p.latency_recorded ? html_number(p.latency.median_ms) + " / " + html_number(p.latency.p95_ms) : "not recorded",
         validation_text(p.validation)});
  }
  if (rows.empty()) return {};
  std::string html = "<h2 id=\"headset\">Headset</h2>\n";
  html +=
      "<p>Sessions run in a head-mounted display through OpenXR (docs/hmd.md). Each frame submits both eyes' "
      "images for one predicted display time (the present clock openxr_predicted_display), so the refresh "
      "intervals, late intervals and dropped frames are each eye's alike; one gaze sample a refresh places both "
      "eyes' pixels (the combined gaze ray resting on the gaze fixation), so its age at present time and the "
      "eye-tracker checks are each eye's alike too. Each eye's field of view is [left, right, up, down] from its "
      "forward direction, with its pixels per degree at the view's centre; the runtime's compositor corrects the "
      "lens. Frames ended late are refreshes handed to the compositor (xrEndFrame) after the display time the "
      "runtime predicted for them, measured where the runtime converts its clock (XR_KHR_convert_timespec_time); "
      "late intervals are refresh intervals beyond 1.5 periods.</p>\n";
  html +=
      html_table({"session", "OpenXR runtime", "each eye (px)", "left eye", "right eye", "view model", "gaze fixation",
                  "present clock", "refresh intervals (both eyes)", "dropped frames", "frames ended late",
                  "gaze-to-present ms, median / p95", "eye-tracker checks passed / tried; accuracy (worst), precision"},
                 rows);
  return html + html_headset_gaze(result);
}

// The Headline section, first on the page: one row a group, the value only when it is one.
std::string html_headlines(const AnalysisResult& result) {
  std::string html = "<h2 id=\"headline\">Headline</h2>\n";
  if (result.headlines.empty()) return html + "<p>No headline: the analysis gave none for this design.</p>\n";
  html +=
      "<p>The number to publish for each group, with its 95 % interval, the method that gives it and what "
      "that method aims at. A status other than <em>estimated</em> is shown with its reason and no number. "
      "The paper's own rule is beside it; the same in headline.csv and thresholds.json (headlines).</p>\n";
  html += "<div class=\"table\"><table class=\"headline\">\n<thead>" +
          html_row({"group", "quantity", "value [95 % interval]", "status", "method", "aims at", "flags",
                    "participants", "the paper's rule"},
                   true) +
          "</thead>\n<tbody>\n";
  for (const Headline& headline : result.headlines) {
    const bool shown = headline.status == HeadlineStatus::estimated && headline_has_value(headline);
    const std::string row_class = headline.status == HeadlineStatus::not_estimable ? "not-estimable"
                                  : headline.status == HeadlineStatus::biased      ? "biased"
                                                                                   : "estimated";
    const char* no_value = headline.status == HeadlineStatus::biased ? "withheld (biased)" : "none";
    std::string value = shown ? html_escape(headline_value_text(headline)) : no_value;
    std::string status = "<span class=\"status\">" + html_escape(headline_status_name(headline.status)) + "</span>";
    if (!headline.reason.empty()) status += ": " + html_escape(headline.reason);
    std::string paper = "\xE2\x80\x93";
    if (!headline.paper_rule.empty()) {
      paper = html_escape(headline.paper_rule) + ": " +
              (headline.paper_value ? html_escape(html_number(headline.paper_value)) : std::string("no value"));
      if (headline.paper_rule_is_headline) paper += " (chosen as the headline)";
      if (!headline.paper_difference.empty()) paper += "<br>" + html_escape(headline.paper_difference);
    }
    std::string flags = html_escape(joined(headline.flags, "; "));
    html += "<tr class=\"" + row_class + "\"><td>" + html_escape(headline.group.label()) + "</td><td>" +
            html_escape(headline.quantity) + "</td><td class=\"value\">" + value + "</td><td>" + status + "</td><td>" +
            html_escape(headline.method) + "</td><td>" + html_escape(headline.aims_at) + "</td><td>" + flags +
            "</td><td>" + std::to_string(headline.participants) + "</td><td>" + paper + "</td></tr>\n";
  }
  html += "</tbody>\n</table></div>\n";
  // The notes (the fits' among them) and the pooled fit of adaptive designs, per group.
  std::string notes;
  for (const Headline& headline : result.headlines) {
    std::vector<std::string> lines = headline.notes;
    if (headline.pooled_fit)
      lines.insert(lines.begin(), "the pooled fit of every adaptive trial: " +
                                      html_value_with_interval(headline.pooled_fit, headline.pooled_fit_lower,
                                                               headline.pooled_fit_upper));
    for (const std::string& line : lines)
      notes += "<li><strong>" + html_escape(headline.group.label()) + "</strong>: " + html_escape(line) + "</li>\n";
  }
  if (!notes.empty()) html += "<ul class=\"notes\">\n" + notes + "</ul>\n";
  return html;
}

}  // namespace

std::string report_html(const AnalysisResult& result, const ReportPlots& report_plots) {
  const std::vector<Plot>& plots = report_plots.figures;
  int included = 0;
  int excluded = 0;
  for (const ParticipantRow& participant : result.participants) (participant.excluded ? excluded : included) += 1;

  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<title>fovlab analysis: " + html_escape(result.study) + "</title>\n<style>\n" + kStyle + "</style>\n";
  html += "</head>\n<body>\n<h1>fovlab analysis: " + html_escape(result.study) + "</h1>\n";
  html += html_headlines(result);

  html += "<h2 id=\"summary\">Study</h2>\n<dl>\n";
  auto item = [&](const std::string& term, const std::string& value) {
    html += "<dt>" + html_escape(term) + "</dt><dd>" + html_escape(value) + "</dd>\n";
  };
  item("Study", result.study);
  const std::string question(result.rules().question_name);
  item("Protocol", std::string(result.rules().name) + (question.empty() ? "" : " (question: " + question + ")"));
  if (!result.level_parameter.empty()) {
    item("Level parameter",
         result.level_parameter + (result.higher_is_better ? " (higher is better)" : " (lower is better)"));
  }
  std::string levels;
  for (double level : result.levels) {
    if (!levels.empty()) levels += ", ";
    levels += html_number(level);
  }
  item("Levels", levels.empty() ? "none" : levels);
  item("Inputs", std::to_string(result.inputs.size()) + (result.inputs.size() == 1 ? " session log" : " session logs"));
  for (const ConfigVersion& version : result.config_versions)
    item(result.config_versions.size() == 1 ? "Config version" : "Config versions (only one is analysed)",
         describe_config_version(version));
  item("Participants", std::to_string(included) + " included, " + std::to_string(excluded) + " excluded");
  item("Observers", result.observers == "human"       ? "human (real participants)"
                    : result.observers == "simulated" ? "simulated observers only: not real participants' data"
                                                      : "human and simulated, pooled on request (--observers all)");
  // Ramps and sliders have no per-condition tests or fits: their thresholds are per participant.
  const bool per_condition = result.protocol != ProtocolKind::ramp && result.protocol != ProtocolKind::slider;
  if (per_condition) {
    item("Test", test_description(result));
    item("Guess rate of the fits", html_number(result.guess_rate) +
                                       (result.guess_rate_source.empty() ? "" : " (" + result.guess_rate_source + ")"));
  }
  html += "</dl>\n";
  if (!result.inputs.empty()) {
    html += "<details><summary>Session logs read</summary>\n<ul>\n";
    for (const std::string& input : result.inputs) html += "<li>" + html_escape(input) + "</li>\n";
    html += "</ul>\n</details>\n";
  }

  html += "<h2 id=\"thresholds\">Thresholds by the paper's rule</h2>\n";
  if (result.thresholds.empty()) {
    html += "<p>No thresholds.</p>\n";
  } else {
    // The definition once: one for every group (the usual case), else one line a group.
    std::vector<std::string> definitions;
    for (const GroupThreshold& t : result.thresholds)
      if (std::find(definitions.begin(), definitions.end(), t.definition) == definitions.end())
        definitions.push_back(t.definition);
    // Several (pair: pooled and per participant): each once, numbered, and each row names its number.
    const bool several = definitions.size() > 1;
    const auto number_of = [&](const std::string& definition) {
      return "(" +
             std::to_string(std::find(definitions.begin(), definitions.end(), definition) - definitions.begin() + 1) +
             ")";
    };
    if (!several) {
      html += "<p class=\"definition\"><strong>Definition</strong>: " + html_escape(definitions.front()) + "</p>\n";
    } else {
      html +=
          "<p class=\"definition\"><strong>Definitions</strong> (the table's column names which):</p>\n"
          "<ul class=\"definition\">\n";
      for (const std::string& definition : definitions)
        html += "<li>" + html_escape(number_of(definition)) + " " + html_escape(definition) + "</li>\n";
      html += "</ul>\n";
    }
    std::vector<std::vector<std::string>> rows;
    for (const GroupThreshold& t : result.thresholds) {
      // A pooled rule (the walk) counts no participants: its participant columns are a dash.
      const bool per_participant = t.participants_with_threshold + t.participants_without_threshold > 0;
      const std::string dash = "\xE2\x80\x93";
      std::vector<std::string> row = {t.group.scene, t.group.variant};
      if (several) row.push_back(number_of(t.definition));
      row.insert(row.end(), {t.unsupported ? "none (see note)" : html_number(t.level), html_number(t.mean),
                             t.mean_lower ? html_interval(*t.mean_lower, *t.mean_upper) : std::string("\xE2\x80\x93"),
                             html_number(t.sd), per_participant ? std::to_string(t.participants_with_threshold) : dash,
                             per_participant ? std::to_string(t.participants_without_threshold) : dash, t.note});
      rows.push_back(std::move(row));
    }
    std::vector<std::string> header = {"scene", "variant"};
    if (several) header.push_back("definition");
    header.insert(header.end(), {"threshold", "mean over participants", "95 % CI of the mean", "SD",
                                 "participants with a threshold", "participants without", "note"});
    html += html_table(header, rows);
  }

  if (result.rating_grid) {
    const RatingGrid& grid = *result.rating_grid;
    html += "<h2 id=\"rating-grid\">Pilot grid</h2>\n<p>Ye et al. 2022, 4.4.1: the mean score of each pair of " +
            html_escape(grid.x_key) + " and " + html_escape(grid.y_key) +
            " (each participant's mean over the pair's trials, then the mean over participants), over every level; "
            "the pair with the highest mean per block. Every cell and level: rating_grid.csv.</p>\n";
    std::vector<std::vector<std::string>> rows;
    for (const GridMap& map : grid.maps) {
      if (map.level) continue;
      std::string pairs;
      for (std::size_t index : map.best) {
        pairs += (pairs.empty() ? "(" : "; (") + html_number(map.cells[index].x) + ", " +
                 html_number(map.cells[index].y) + ")";
      }
      uint64_t trials = 0;
      for (const GridCell& cell : map.cells) trials += cell.trials;
      rows.push_back({map.scene, pairs.empty() ? "\xE2\x80\x93" : pairs,
                      map.best.empty() ? "\xE2\x80\x93" : html_number(map.cells[map.best.front()].mean_score),
                      map.best.size() > 1 ? "tie of " + std::to_string(map.best.size()) + " pairs" : "",
                      std::to_string(trials)});
    }
    html += html_table({"scene", "best (" + grid.x_key + ", " + grid.y_key + ")", "mean score", "tie", "trials"}, rows);
  }

  if (!result.preferences.empty()) {
    html +=
        "<h2 id=\"preference\">Preference table</h2>\n<p>Ye et al. 2022, Table 2: the votes for the reference "
        "stimulus. Test: exact binomial, one-sided (greater: the reference preferred), H0 p = 1/2, whatever "
        "--alternative says, no correction; CI: 95 % Clopper-Pearson of the share.</p>\n";
    std::vector<std::vector<std::string>> rows;
    for (const PreferenceRow& row : result.preferences) {
      rows.push_back({row.group.scene, row.group.variant, row.condition,
                      row.reference_method + " v. " + row.test_method,
                      std::to_string(row.reference_votes) + " / " + std::to_string(row.n),
                      format_number(100.0 * row.share, 3) + " %", p_value_text(row.p_value, row.log10_p, kHtmlDigits),
                      row.stars, html_interval(row.interval.lower, row.interval.upper)});
    }
    html += html_table({"scene", "variant", "condition", "reference v. test", "votes for the reference", "share",
                        "p (one-sided)", "stars", "95 % CI"},
                       rows);
  }

  html += "<h2 id=\"plots\">Plots</h2>\n";
  if (plots.empty()) html += "<p>No plots (no data to plot).</p>\n";
  for (const Plot& plot : plots) {
    html += html_figure(plot);
  }

  if (!per_condition) {
    html += "<p>The " + std::string(result.rules().name) +
            " protocol has no per-condition tests or psychometric fits: its threshold is defined per participant "
            "(Thresholds above; per ramp or per saved level in Participants below).</p>\n";
  }
  if (per_condition) html += "<h2 id=\"fits\">Psychometric fits</h2>\n";
  std::vector<std::vector<std::string>> fit_rows;
  std::vector<std::string> not_fitted;
  for (const GroupFit& group : result.fits) {
    for (const PsychometricFit& fit : group.fits) {
      const PsychometricParameters& p = fit.model.parameters;
      fit_rows.push_back(
          {group.group.scene, group.group.variant, shape_name(fit.model.shape), fit.model.rising ? "rising" : "falling",
           html_number(p.threshold), html_interval(fit.threshold_interval.lower, fit.threshold_interval.upper),
           html_number(p.slope), html_interval(fit.slope_interval.lower, fit.slope_interval.upper),
           html_number(p.lapse), html_interval(fit.lapse_interval.lower, fit.lapse_interval.upper),
           html_number(fit.model.guess), html_number(fit.deviance), std::to_string(fit.degrees_of_freedom),
           html_number(fit.deviance_p_value), html_number(fit.log_likelihood), fit.converged ? "yes" : "no",
           std::to_string(fit.bootstrap_samples) + " / " + std::to_string(fit.bootstrap_failures), fit.note});
    }
    for (const std::string& reason : group.not_fitted) not_fitted.push_back(group.group.label() + ": " + reason);
  }
  if (fit_rows.empty()) {
    if (per_condition) html += "<p>No fits.</p>\n";
  } else {
    html += html_table(
        {"scene", "variant", "shape", "direction", "threshold", "threshold CI", "slope", "slope CI", "lapse",
         "lapse CI", "guess", "deviance", "dof", "p (deviance)", "log L", "converged", "bootstrap ok / failed", "note"},
        fit_rows);
  }
  if (!not_fitted.empty()) {
    html += "<p>Not fitted:</p>\n<ul>\n";
    for (const std::string& line : not_fitted) html += "<li>" + html_escape(line) + "</li>\n";
    html += "</ul>\n";
  }

  if (per_condition)
    html += "<h2 id=\"conditions\">Conditions</h2>\n<p>Test: " + html_escape(test_description(result)) +
            "; k counts the trials where the test was " + std::string(result.rules().judged_words) +
            "; CI: 95 % Clopper-Pearson.</p>\n";
  if (result.conditions.empty()) {
    if (per_condition) html += "<p>No conditions.</p>\n";
  } else {
    const bool ratings = std::any_of(result.conditions.begin(), result.conditions.end(),
                                     [](const ConditionRow& row) { return row.mean_rating.has_value(); });
    std::vector<std::string> header = {"scene", "variant", "method",  "condition", "level",    "n",
                                       "k",     "k/n",     "95 % CI", "p",         "p (Holm)", "stars"};
    if (ratings) header.insert(header.end(), {"mean rating", "SD rating"});
    std::vector<std::vector<std::string>> rows;
    for (const ConditionRow& row : result.conditions) {
      std::vector<std::string> cells = {row.group.scene,
                                        row.group.variant,
                                        row.method,
                                        row.condition,
                                        html_number(row.level),
                                        std::to_string(row.n),
                                        std::to_string(row.k),
                                        html_number(row.proportion),
                                        html_interval(row.interval.lower, row.interval.upper),
                                        p_value_text(row.p_value, row.log10_p, kHtmlDigits),
                                        html_number(row.p_holm),
                                        shown_stars(result, row)};
      if (ratings) cells.insert(cells.end(), {html_number(row.mean_rating), html_number(row.sd_rating)});
      rows.push_back(std::move(cells));
    }
    html += html_table(header, rows);
  }

  html += "<h2 id=\"participants\">Participants</h2>\n";
  if (result.participants.empty()) {
    html += "<p>No participants.</p>\n";
  } else {
    std::vector<std::vector<std::string>> rows;
    for (const ParticipantRow& p : result.participants) {
      const std::vector<std::string> common = {
          p.participant,
          p.observer,
          p.excluded ? "yes" : "no",
          p.session_ended ? "yes" : "no",
          p.log_note.empty() ? log_status_name(p.log_status) : p.log_note,
          std::to_string(p.complete_trials) +
              (p.practice_trials ? " (+" + std::to_string(p.practice_trials) + " practice)" : ""),
          std::to_string(p.attention_errors) + " / " + std::to_string(p.attention_checks),
          p.latency_recorded
              ? html_number(p.latency.median_ms) + " / " + html_number(p.latency.p95_ms) + " (" + p.present_clock + ")"
              : "not recorded",
          std::to_string(p.dropped_frames),
          gaze_source_cell(p),
          validation_text(p.validation)};
      if (p.thresholds.empty()) {
        auto cells = common;
        cells.insert(cells.end(), {"", "", "", ""});
        rows.push_back(std::move(cells));
      }
      for (const ParticipantThreshold& t : p.thresholds) {
        auto cells = common;
        cells.insert(cells.end(), {t.group.scene, t.group.variant, html_number(t.level), t.note});
        rows.push_back(std::move(cells));
      }
    }
    html += html_table(
        {"participant", "observer", "excluded", "session ended", "log", "complete trials", "attention errors / checks",
         "gaze-to-present ms, median / p95 (clock)", "dropped frames", "gaze source",
         "eye-tracker checks passed / tried; accuracy (worst), precision", "scene", "variant", "threshold", "note"},
        rows);
  }

  html += html_frame_intervals(result, report_plots.frame_intervals);
  html += html_headset(result);

  const bool with_tracks = has_adaptive_tracks(result);
  if (with_tracks) {
    html +=
        "<h2 id=\"adaptive\">Adaptive tracks</h2>\n<p>Each adaptive track's threshold by its procedure's rule "
        "(docs/analysis.md): a staircase's mean level of its last reversals; QUEST+'s posterior mean, with its 95 % "
        "credible interval. The tracks are plotted above and listed in adaptive_tracks.csv.</p>\n";
    std::vector<std::vector<std::string>> rows;
    for (const ParticipantRow& p : result.participants)
      for (const AdaptiveTrackResult& track : p.tracks)
        rows.push_back({p.participant, track.block, track.procedure, track.variant,
                        track.start_level ? html_number(*track.start_level) : "", std::to_string(track.levels.size()),
                        track.kind == "staircase" ? std::to_string(track.reversal_trials.size()) : "",
                        track.stopped ? "yes" : "no", html_number(track.threshold),
                        track.threshold_lower ? html_interval(*track.threshold_lower, *track.threshold_upper) : "",
                        track.note});
    html += html_table({"participant", "block", "procedure", "variant", "start", "trials", "reversals", "stopped",
                        "threshold", "95 % credible interval", "note"},
                       rows);
  }

  html += "<h2 id=\"left-out\">Left out</h2>\n";
  if (result.left_out.empty()) {
    html += "<p>nothing</p>\n";
  } else {
    html += "<ul>\n";
    for (const LeftOut& left : result.left_out) {
      html += "<li><strong>" + html_escape(left.what) + "</strong>: " + html_escape(left.reason) + "</li>\n";
    }
    html += "</ul>\n";
  }
  html += std::string("<p>The same numbers as data: headline.csv, conditions.csv, participants.csv, ") +
          (with_tracks ? "adaptive_tracks.csv, " : "") + "thresholds.json.</p>\n";
  html += html_references(html);
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace fovlab::analysis::report_detail
