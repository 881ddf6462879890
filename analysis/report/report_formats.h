#pragma once
// Internals of the analysis report (report.h), one file a format: report_csv.cpp (the CSV tables),
// report_json.cpp (thresholds.json), report_plots.cpp (the SVG plots, drawn by svg_chart.h),
// report_html.cpp (report.html), and report_text.cpp (the text every format shares: numbers as the
// tables print them, a headline's value, a condition's stars). report.cpp writes them as one set.
#include <optional>
#include <string>
#include <vector>

#include "analysis/study/analysis_result.h"

namespace fovlab::analysis::report_detail {

constexpr int kHtmlDigits = 4;  // significant digits of numbers in the HTML tables and plot labels (people read them)

// ---- text every format shares (report_text.cpp) ----

// Numbers in the HTML tables: 4 significant digits, "–" for none.
std::string html_number(double value);
std::string html_number(const std::optional<double>& value);
// "[11.73, 13.27]" at 4 significant digits (format_interval: an unbounded end as "∞)"); "–" when
// an end is NaN (not computed).
std::string html_interval(double lower, double upper);
// "13.81 [12.96, 14.71]": a value with its 95 % interval, the interval left out when an end is missing.
std::string html_value_with_interval(const std::optional<double>& value, const std::optional<double>& lower,
                                     const std::optional<double>& upper);

// The stars a condition row shows (docs/analysis.md, "Significance stars in the outputs").
std::string shown_stars(const AnalysisResult& result, const ConditionRow& row);

// Whether a headline's value may be printed: never when not estimable (whatever the struct holds);
// its value and interval where it may, else none.
bool headline_has_value(const Headline& headline);
std::optional<double> headline_value(const Headline& headline);
std::optional<double> headline_lower(const Headline& headline);
std::optional<double> headline_upper(const Headline& headline);
// "12.5 [11.73, 13.27]": a headline's value with its 95 % interval ("no interval" when it has none).
std::string headline_value_text(const Headline& headline);

std::string joined(const std::vector<std::string>& items, const std::string& separator);

// The gaze source the session's runs used ("not recorded" when its log names none).
std::string gaze_source_cell(const ParticipantRow& participant);

// Whether any participant ran an adaptive track (then adaptive_tracks.csv is written).
bool has_adaptive_tracks(const AnalysisResult& result);

// ---- the files, one function a format ----

// report_csv.cpp: one CSV text a file (RFC 4180, core/csv.h).
std::string headline_csv(const AnalysisResult& result);
std::string conditions_csv(const AnalysisResult& result);
std::string participants_csv(const AnalysisResult& result);
std::string adaptive_tracks_csv(const AnalysisResult& result);
std::string rating_grid_csv(const RatingGrid& grid, const std::string& study);
std::string preference_csv(const AnalysisResult& result);

// report_json.cpp: thresholds.json's text (docs/analysis.md), ending in a newline.
std::string thresholds_json_text(const AnalysisResult& result);

// report_plots.cpp: a plot as its file and its caption in the HTML.
struct Plot {
  std::string file_name;
  std::string caption;
  std::string svg;
};
struct ReportPlots {
  std::vector<Plot> figures;          // the Plots section, in order
  std::vector<Plot> frame_intervals;  // the Frame intervals section: the study's, then one a session
};
// Every plot of the analysis, each with a file name of its own.
ReportPlots report_plots(const AnalysisResult& result);

// report_html.cpp: the page, the plots inline.
std::string report_html(const AnalysisResult& result, const ReportPlots& plots);

}  // namespace fovlab::analysis::report_detail
