#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "analysis/report/report_formats.h"
#include "core/number_text.h"

namespace fovlab::analysis::report_detail {

std::string html_number(double value) {
  return std::isfinite(value) ? format_number(value, kHtmlDigits) : "\xE2\x80\x93";
}
std::string html_number(const std::optional<double>& value) { return value ? html_number(*value) : "\xE2\x80\x93"; }

std::string html_interval(double lower, double upper) {
  const std::string text = format_interval(lower, upper, kHtmlDigits);
  return text.empty() ? "\xE2\x80\x93" : text;
}

std::string html_value_with_interval(const std::optional<double>& value, const std::optional<double>& lower,
                                     const std::optional<double>& upper) {
  return html_number(value) + (lower && upper ? " " + html_interval(*lower, *upper) : std::string());
}

// The stars a condition row shows (docs/analysis.md, "Significance stars in the outputs"): a
// one-sided test's as they are (its alternative names the direction); a two-sided test's only where
// the share in favour of the test is below 1/2, the direction in which the threshold counts a level
// as distinguished. A two-sided p below alpha with the share above 1/2 says the test was favoured,
// not that it was told apart: its p is shown, without stars.
std::string shown_stars(const AnalysisResult& result, const ConditionRow& row) {
  if (result.alternative != Alternative::two_sided) return row.stars;
  return row.proportion < 0.5 ? row.stars : std::string();
}

// Whether a headline's value may be printed: never when not estimable (whatever the struct holds).
bool headline_has_value(const Headline& headline) {
  return headline.status != HeadlineStatus::not_estimable && headline.value && std::isfinite(*headline.value);
}
std::optional<double> headline_value(const Headline& headline) {
  return headline_has_value(headline) ? headline.value : std::nullopt;
}
std::optional<double> headline_lower(const Headline& headline) {
  return headline_has_value(headline) ? headline.lower : std::nullopt;
}
std::optional<double> headline_upper(const Headline& headline) {
  return headline_has_value(headline) ? headline.upper : std::nullopt;
}

std::string joined(const std::vector<std::string>& items, const std::string& separator) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : separator) + item;
  return text;
}

// "12.5 [11.73, 13.27]": a headline's value with its 95 % interval ("no interval" when it has none).
std::string headline_value_text(const Headline& headline) {
  if (!headline.lower || !headline.upper) return html_number(*headline.value) + " (no interval)";
  return html_value_with_interval(headline.value, headline.lower, headline.upper);
}

// The gaze source the session's runs used ("tracker", "mouse", "tracker+mouse", ...; "not recorded"
// when its log names none).
std::string gaze_source_cell(const ParticipantRow& participant) {
  return participant.gaze_source.empty() ? "not recorded" : participant.gaze_source;
}

bool has_adaptive_tracks(const AnalysisResult& result) {
  return std::any_of(result.participants.begin(), result.participants.end(),
                     [](const ParticipantRow& participant) { return !participant.tracks.empty(); });
}

}  // namespace fovlab::analysis::report_detail
