#include "analysis/report/report.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/report/svg_chart.h"
#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab::analysis {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;  // keys in the documented order

constexpr int kCsvDigits = 10;   // significant digits of numbers in the CSV files
constexpr int kHtmlDigits = 4;   // ... and in the HTML tables (people read them)
constexpr int kCurveSamples = 200;
constexpr size_t kGroupsInOnePlot = 4;  // more groups: one share plot each
constexpr size_t kTrackPlots = 24;       // participants drawn one plot each (adaptive tracks, frame intervals)

// ---- text helpers ----------------------------------------------------------------------------

std::string csv_number(double value) { return std::isfinite(value) ? format_number(value, kCsvDigits) : ""; }
std::string csv_number(const std::optional<double>& value) { return value ? csv_number(*value) : ""; }

// A JSON number, or null for none and for non-finite values (JSON has no NaN).
json json_number(double value) { return std::isfinite(value) ? json(value) : json(nullptr); }
json json_number(const std::optional<double>& value) { return value ? json_number(*value) : json(nullptr); }

// Numbers in the HTML tables: 4 significant digits, "–" for none.
std::string html_number(double value) { return std::isfinite(value) ? format_number(value, kHtmlDigits) : "\xE2\x80\x93"; }
std::string html_number(const std::optional<double>& value) { return value ? html_number(*value) : "\xE2\x80\x93"; }

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

std::string html_interval(double lower, double upper) {
  const std::string text = format_interval(lower, upper, kHtmlDigits);
  return text.empty() ? "\xE2\x80\x93" : text;
}

// Anything outside [A-Za-z0-9_-] becomes '_' (a UTF-8 character: one '_' a byte).
std::string safe_name(const std::string& text) {
  std::string name;
  for (char c : text) {
    const bool keep = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    name += keep ? c : '_';
  }
  return name.empty() ? "unnamed" : name;
}

// A file name not yet taken: stem.svg, else stem_2.svg, stem_3.svg, ...
std::string unique_svg_name(const std::string& stem, std::set<std::string>& taken) {
  std::string name = stem + ".svg";
  for (int i = 2; taken.count(name); ++i) name = stem + "_" + std::to_string(i) + ".svg";
  taken.insert(name);
  return name;
}

// The test as one phrase: "exact binomial, two-sided, H0 p = 1/2, Holm across levels, alpha 0.05".
std::string test_description(const AnalysisResult& result) {
  const std::string sidedness = result.alternative == Alternative::two_sided
                                    ? std::string("two-sided")
                                    : "one-sided (" + std::string(alternative_name(result.alternative)) + ")";
  return "exact binomial, " + sidedness + ", H0 p = 1/2, Holm across levels, alpha " + format_number(result.alpha, 6);
}

bool is_rating(const AnalysisResult& result) { return result.protocol == ProtocolKind::rating; }

std::string level_axis_label(const AnalysisResult& result) {
  return result.level_parameter.empty() ? "level" : "level (" + result.level_parameter + ")";
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
  std::string text = html_number(*headline.value);
  if (headline.lower && headline.upper)
    text += " " + html_interval(*headline.lower, *headline.upper);
  else
    text += " (no interval)";
  return text;
}

// The headline of `group`, if the analysis gave one.
const Headline* headline_of(const AnalysisResult& result, const GroupKey& group) {
  for (const Headline& headline : result.headlines)
    if (headline.group == group) return &headline;
  return nullptr;
}

// The headline is an estimated threshold on the level axis (not a preference share): marked on its
// plots. A biased or not estimable one is not (the plot's caption says why), as the Headline table
// prints no number for it.
bool marks_level(const Headline* headline) {
  return headline && headline->status == HeadlineStatus::estimated && headline->quantity != "preference share" &&
         headline_has_value(*headline);
}

// ---- CSV -------------------------------------------------------------------------------------

std::string conditions_csv(const AnalysisResult& result) {
  std::string csv = csv_line({"study", "protocol", "scene", "variant", "method", "condition", "level", "n", "k", "proportion",
                              "ci_lower", "ci_upper", "p_value", "p_holm", "stars", "alternative", "mean_rating",
                              "sd_rating", "log10_p"});
  for (const ConditionRow& row : result.conditions) {
    csv += csv_line({result.study, std::string(result.rules().name), row.group.scene,
                     row.group.variant, row.method, row.condition, csv_number(row.level),
                     std::to_string(row.n), std::to_string(row.k), csv_number(row.proportion),
                     csv_number(row.interval.lower), csv_number(row.interval.upper), csv_number(row.p_value),
                     csv_number(row.p_holm), shown_stars(result, row), alternative_name(result.alternative),
                     csv_number(row.mean_rating), csv_number(row.sd_rating), csv_number(row.log10_p)});
  }
  return csv;
}

// The latency columns of a participant: median and p95 (ms), refreshes counted, dropped frames and
// the present clock ("not recorded" for a log older than schema 3, whose latency cells are empty).
std::vector<std::string> latency_cells(const ParticipantRow& participant) {
  if (!participant.latency_recorded)
    return {"", "", "", std::to_string(participant.dropped_frames), "not recorded"};
  return {csv_number(participant.latency.median_ms), csv_number(participant.latency.p95_ms),
          std::to_string(participant.latency.refreshes), std::to_string(participant.dropped_frames),
          participant.present_clock};
}

// The frame-interval columns: the refresh rate they are measured against, the intervals counted,
// their median, SD, p99 and max (ms), and the late ones (beyond 1.5 refresh periods), as a count
// and a share; empty numbers without intervals.
std::vector<std::string> frame_interval_cells(const FrameIntervalSummary& frames) {
  return {csv_number(frames.refresh_hz), std::to_string(frames.intervals), csv_number(frames.median_ms),
          csv_number(frames.sd_ms),      csv_number(frames.p99_ms),        csv_number(frames.max_ms),
          frames.intervals ? std::to_string(frames.late) : "",              csv_number(frames.late_share)};
}

// The eye-tracker validation columns: attempts, passed, and over the passed ones the mean and worst
// accuracy and the mean precision (all empty when the study validated nothing).
std::vector<std::string> validation_cells(const ParticipantRow& participant) {
  const ValidationSummary& validation = participant.validation;
  if (validation.attempts == 0) return {"", "", "", "", ""};
  return {std::to_string(validation.attempts), std::to_string(validation.passed), csv_number(validation.mean_accuracy_deg),
          csv_number(validation.worst_accuracy_deg), csv_number(validation.mean_precision_deg)};
}

// The gaze source the session's runs used ("tracker", "mouse", "tracker+mouse", ...; "not recorded"
// when its log names none).
std::string gaze_source_cell(const ParticipantRow& participant) {
  return participant.gaze_source.empty() ? "not recorded" : participant.gaze_source;
}

// adaptive_tracks.csv: one row a participant's adaptive track (staircase or QUEST+), with its
// threshold by the procedure's rule and its levels and answers (';'-separated, in trial order).
std::string adaptive_tracks_csv(const AnalysisResult& result) {
  std::string csv = csv_line({"participant", "observer", "excluded", "block", "procedure", "kind", "variant", "track",
                              "start_level", "trials", "reversals", "stopped", "threshold", "threshold_lower",
                              "threshold_upper", "slope", "lapse", "note", "levels", "seen"});
  for (const ParticipantRow& participant : result.participants)
    for (const AdaptiveTrackResult& track : participant.tracks) {
      std::string levels, seen;
      for (size_t i = 0; i < track.levels.size(); ++i) {
        levels.append(i ? ";" : "").append(csv_number(track.levels[i]));
        seen.append(i ? ";" : "").append(track.seen[i] ? "1" : "0");
      }
      const bool staircase = track.kind == "staircase";
      csv += csv_line({participant.participant, participant.observer, participant.excluded ? "true" : "false", track.block,
                       track.procedure, track.kind, track.variant, std::to_string(track.track), csv_number(track.start_level),
                       std::to_string(track.levels.size()), staircase ? std::to_string(track.reversal_trials.size()) : "",
                       track.stopped ? "true" : "false", csv_number(track.threshold), csv_number(track.threshold_lower),
                       csv_number(track.threshold_upper), csv_number(track.slope), csv_number(track.lapse), track.note,
                       levels, seen});
    }
  return csv;
}

json adaptive_tracks_json(const ParticipantRow& participant) {
  json tracks = json::array();
  for (const AdaptiveTrackResult& track : participant.tracks) {
    json levels = json::array();
    for (double level : track.levels) levels.push_back(json_number(level));
    json entry = {{"track", track.track},       {"block", track.block},   {"procedure", track.procedure},
                  {"kind", track.kind},         {"variant", track.variant}, {"levels", levels},
                  {"seen", track.seen},         {"stopped", track.stopped}, {"threshold", json_number(track.threshold)},
                  {"note", track.note}};
    if (track.kind == "staircase") {
      entry["start_level"] = json_number(track.start_level);
      entry["reversal_trials"] = track.reversal_trials;
      entry["reversals_averaged"] = track.reversals_averaged;
    } else {
      entry["threshold_lower"] = json_number(track.threshold_lower);
      entry["threshold_upper"] = json_number(track.threshold_upper);
      entry["slope"] = json_number(track.slope);
      entry["lapse"] = json_number(track.lapse);
    }
    tracks.push_back(std::move(entry));
  }
  return tracks;
}

std::string participants_csv(const AnalysisResult& result) {
  std::string csv = csv_line({"participant", "observer", "excluded", "session_ended", "complete_trials", "attention_checks",
                              "attention_errors", "scene", "variant", "threshold", "note", "log_status",
                              "latency_median_ms", "latency_p95_ms", "latency_refreshes", "dropped_frames",
                              "present_clock", "practice_trials", "validation_attempts", "validations_passed",
                              "validation_accuracy_deg", "validation_worst_accuracy_deg", "validation_precision_deg",
                              "gaze_source",
                              "refresh_hz", "frame_intervals", "frame_interval_median_ms", "frame_interval_sd_ms",
                              "frame_interval_p99_ms", "frame_interval_max_ms", "frame_intervals_late",
                              "frame_intervals_late_share"});
  for (const ParticipantRow& participant : result.participants) {
    const std::vector<std::string> common = {
        participant.participant,          participant.observer, participant.excluded ? "true" : "false",
        participant.session_ended ? "true" : "false", std::to_string(participant.complete_trials),
        std::to_string(participant.attention_checks), std::to_string(participant.attention_errors)};
    // After the threshold's: latency and frames, practice trials, eye-tracker validation.
    std::vector<std::string> tail = latency_cells(participant);
    tail.push_back(std::to_string(participant.practice_trials));
    for (std::string& cell : validation_cells(participant)) tail.push_back(std::move(cell));
    tail.push_back(gaze_source_cell(participant));
    for (std::string& cell : frame_interval_cells(participant.frame_intervals)) tail.push_back(std::move(cell));
    if (participant.thresholds.empty()) {
      std::vector<std::string> cells = common;
      cells.insert(cells.end(), {"", "", "", "", log_status_name(participant.log_status)});
      cells.insert(cells.end(), tail.begin(), tail.end());
      csv += csv_line(cells);
    }
    for (const ParticipantThreshold& threshold : participant.thresholds) {
      std::vector<std::string> cells = common;
      cells.insert(cells.end(), {threshold.group.scene, threshold.group.variant,
                                 csv_number(threshold.level), threshold.note, log_status_name(participant.log_status)});
      cells.insert(cells.end(), tail.begin(), tail.end());
      csv += csv_line(cells);
    }
  }
  return csv;
}

// Ye et al. 2022's pilot grid: one row per map and cell.
std::string rating_grid_csv(const RatingGrid& grid, const std::string& study) {
  std::string csv = csv_line({"study", "scene", "level", "x_key", "x", "y_key", "y", "mean_score", "trials",
                              "participants", "best"});
  for (const GridMap& map : grid.maps) {
    for (std::size_t i = 0; i < map.cells.size(); ++i) {
      const GridCell& cell = map.cells[i];
      const bool best = std::find(map.best.begin(), map.best.end(), i) != map.best.end();
      csv += csv_line({study, map.scene, csv_number(map.level), grid.x_key, csv_number(cell.x), grid.y_key,
                       csv_number(cell.y), csv_number(cell.mean_score), std::to_string(cell.trials),
                       std::to_string(cell.participants), best ? "true" : "false"});
    }
  }
  return csv;
}

// Ye et al. 2022's Table 2: one row per condition, the votes for the reference, one-sided.
std::string preference_csv(const AnalysisResult& result) {
  std::string csv = csv_line({"study", "scene", "variant", "condition", "reference_method", "test_method", "n",
                              "reference_votes", "share", "ci_lower", "ci_upper", "p_value", "alternative", "stars",
                              "log10_p"});
  for (const PreferenceRow& row : result.preferences) {
    csv += csv_line({row.study, row.group.scene, row.group.variant, row.condition, row.reference_method, row.test_method,
                     std::to_string(row.n), std::to_string(row.reference_votes), csv_number(row.share),
                     csv_number(row.interval.lower), csv_number(row.interval.upper), csv_number(row.p_value), "greater",
                     row.stars, csv_number(row.log10_p)});
  }
  return csv;
}

// headline.csv: one row a (scene, variant) group, the number to publish with its interval, status
// and method, and the paper's rule beside it (docs/analysis.md). No value when not estimable.
std::string headline_csv(const AnalysisResult& result) {
  std::string csv = csv_line({"scene", "variant", "quantity", "value", "lower", "upper", "status", "reason", "method",
                              "aims_at", "flags", "participants", "paper_rule", "paper_value", "paper_difference",
                              "paper_rule_is_headline", "pooled_fit", "pooled_fit_lower", "pooled_fit_upper", "notes"});
  for (const Headline& headline : result.headlines) {
    csv += csv_line({headline.group.scene, headline.group.variant, headline.quantity, csv_number(headline_value(headline)),
                     csv_number(headline_lower(headline)), csv_number(headline_upper(headline)),
                     headline_status_name(headline.status), headline.reason, headline.method, headline.aims_at,
                     joined(headline.flags, "; "), std::to_string(headline.participants), headline.paper_rule,
                     csv_number(headline.paper_value), headline.paper_difference,
                     headline.paper_rule_is_headline ? "true" : "false", csv_number(headline.pooled_fit),
                     csv_number(headline.pooled_fit_lower), csv_number(headline.pooled_fit_upper),
                     joined(headline.notes, "; ")});
  }
  return csv;
}

// ---- JSON ------------------------------------------------------------------------------------

// One headline in thresholds.json's `headlines`: value and interval null when not estimable.
json headline_json(const Headline& headline) {
  json pooled = nullptr;
  if (headline.pooled_fit)
    pooled = {{"value", json_number(headline.pooled_fit)},
              {"interval", {{"lower", json_number(headline.pooled_fit_lower)}, {"upper", json_number(headline.pooled_fit_upper)}}}};
  return {{"scene", headline.group.scene},
          {"variant", headline.group.variant},
          {"quantity", headline.quantity},
          {"value", json_number(headline_value(headline))},
          {"interval", {{"lower", json_number(headline_lower(headline))}, {"upper", json_number(headline_upper(headline))}}},
          {"method", headline.method},
          {"aims_at", headline.aims_at},
          {"status", headline_status_name(headline.status)},
          {"reason", headline.reason},
          {"flags", headline.flags},
          {"notes", headline.notes},
          {"participants", headline.participants},
          {"paper_rule", headline.paper_rule},
          {"paper_value", json_number(headline.paper_value)},
          {"paper_difference", headline.paper_difference},
          {"paper_rule_is_headline", headline.paper_rule_is_headline},
          {"pooled_fit", pooled}};
}

// A frame-interval summary in thresholds.json (participants' and the study's).
json frame_intervals_json(const FrameIntervalSummary& frames) {
  return {{"refresh_hz", json_number(frames.refresh_hz)},
          {"late_beyond_ms", frames.refresh_hz ? json_number(kLateRefreshPeriods * 1e3 / *frames.refresh_hz) : json(nullptr)},
          {"intervals", frames.intervals},
          {"median_ms", json_number(frames.median_ms)},
          {"sd_ms", json_number(frames.sd_ms)},
          {"p99_ms", json_number(frames.p99_ms)},
          {"max_ms", json_number(frames.max_ms)},
          {"late", frames.late},
          {"late_share", json_number(frames.late_share)}};
}

// null: not computed, or (profile intervals) an end the data do not bound; the fit's note says which.
json interval_json(const ParameterInterval& interval) {
  return {{"lower", json_number(interval.lower)}, {"upper", json_number(interval.upper)}};
}

// A participant's latency in thresholds.json: null numbers and "recorded": false for logs older
// than schema 3.
// A participant's eye-tracker validations in thresholds.json: null when the study validated nothing.
json validation_json(const ParticipantRow& participant) {
  const ValidationSummary& validation = participant.validation;
  if (validation.attempts == 0) return nullptr;
  return {{"attempts", validation.attempts},
          {"passed", validation.passed},
          {"mean_accuracy_deg", json_number(validation.mean_accuracy_deg)},
          {"worst_accuracy_deg", json_number(validation.worst_accuracy_deg)},
          {"mean_precision_deg", json_number(validation.mean_precision_deg)}};
}

json latency_json(const ParticipantRow& participant) {
  return {{"recorded", participant.latency_recorded},
          {"median_ms", json_number(participant.latency.median_ms)},
          {"p95_ms", json_number(participant.latency.p95_ms)},
          {"refreshes", participant.latency.refreshes},
          {"dropped_frames", participant.dropped_frames},
          {"present_clock", participant.latency_recorded ? json(participant.present_clock) : json(nullptr)}};
}

json thresholds_json(const AnalysisResult& result) {
  json root;
  root["study"] = result.study;
  root["observers"] = result.observers;
  root["protocol"] = result.rules().name;
  root["question"] = result.rules().question_name;
  root["level_parameter"] = result.level_parameter;
  root["higher_is_better"] = result.higher_is_better;
  root["levels"] = json::array();
  for (double level : result.levels) root["levels"].push_back(json_number(level));
  root["test"] = {{"kind", "exact binomial"},
                  {"null_proportion", 0.5},
                  {"alternative", alternative_name(result.alternative)},
                  {"alpha", json_number(result.alpha)},
                  {"correction", "holm"}};
  root["guess_rate"] = json_number(result.guess_rate);
  root["guess_rate_source"] = result.guess_rate_source;
  root["inputs"] = result.inputs;
  root["headlines"] = json::array();
  for (const Headline& headline : result.headlines) root["headlines"].push_back(headline_json(headline));

  root["thresholds"] = json::array();
  for (const GroupThreshold& threshold : result.thresholds) {
    root["thresholds"].push_back({{"scene", threshold.group.scene},
                                  {"variant", threshold.group.variant},
                                  {"definition", threshold.definition},
                                  {"level", json_number(threshold.level)},
                                  {"supported", !threshold.unsupported},
                                  {"note", threshold.note},
                                  {"mean", json_number(threshold.mean)},
                                  {"sd", json_number(threshold.sd)},
                                  {"mean_interval", {{"lower", json_number(threshold.mean_lower)},
                                                     {"upper", json_number(threshold.mean_upper)}}},
                                  {"participants_with_threshold", threshold.participants_with_threshold},
                                  {"participants_without_threshold", threshold.participants_without_threshold}});
  }

  root["fits"] = json::array();
  root["not_fitted"] = json::array();
  for (const GroupFit& group : result.fits) {
    json data = json::array();
    for (const LevelCounts& counts : group.data) {
      data.push_back({{"level", json_number(counts.level)},
                      {"n", counts.n},
                      {"k_difference", counts.k},
                      {"proportion", counts.n > 0 ? json_number(static_cast<double>(counts.k) /
                                                                static_cast<double>(counts.n))
                                                  : json(nullptr)}});
    }
    for (const PsychometricFit& fit : group.fits) {
      const PsychometricModel& model = fit.model;
      root["fits"].push_back({{"scene", group.group.scene},
                              {"variant", group.group.variant},
                              {"shape", shape_name(model.shape)},
                              {"rising", model.rising},
                              {"threshold", json_number(model.parameters.threshold)},
                              {"slope", json_number(model.parameters.slope)},
                              {"lapse", json_number(model.parameters.lapse)},
                              {"guess", json_number(model.guess)},
                              {"intervals",
                               {{"method", "profile likelihood"},
                                {"threshold", interval_json(fit.threshold_interval)},
                                {"slope", interval_json(fit.slope_interval)},
                                {"lapse", interval_json(fit.lapse_interval)}}},
                              {"bootstrap_intervals",
                               {{"method", "parametric bootstrap, percentile"},
                                {"threshold", interval_json(fit.bootstrap_threshold_interval)},
                                {"slope", interval_json(fit.bootstrap_slope_interval)},
                                {"lapse", interval_json(fit.bootstrap_lapse_interval)}}},
                              {"deviance", json_number(fit.deviance)},
                              {"dof", fit.degrees_of_freedom},
                              {"deviance_p_value", json_number(fit.deviance_p_value)},
                              {"log_likelihood", json_number(fit.log_likelihood)},
                              {"converged", fit.converged},
                              {"note", fit.note},
                              {"bootstrap_samples", fit.bootstrap_samples},
                              {"bootstrap_failures", fit.bootstrap_failures},
                              {"data", data}});
    }
    for (const std::string& reason : group.not_fitted) {
      root["not_fitted"].push_back(
          {{"scene", group.group.scene}, {"variant", group.group.variant}, {"reason", reason}});
    }
  }

  root["conditions"] = json::array();
  for (const ConditionRow& row : result.conditions) {
    root["conditions"].push_back({{"scene", row.group.scene},
                                  {"variant", row.group.variant},
                                  {"method", row.method},
                                  {"condition", row.condition},
                                  {"level", json_number(row.level)},
                                  {"n", row.n},
                                  {"k", row.k},
                                  {"proportion", json_number(row.proportion)},
                                  {"ci_lower", json_number(row.interval.lower)},
                                  {"ci_upper", json_number(row.interval.upper)},
                                  {"p_value", json_number(row.p_value)},
                                  {"log10_p", json_number(row.log10_p)},
                                  {"p_holm", json_number(row.p_holm)},
                                  {"stars", shown_stars(result, row)},
                                  {"mean_rating", json_number(row.mean_rating)},
                                  {"sd_rating", json_number(row.sd_rating)}});
  }

  root["rating_grid"] = nullptr;
  if (result.rating_grid) {
    const RatingGrid& grid = *result.rating_grid;
    json maps = json::array();
    for (const GridMap& map : grid.maps) {
      json cells = json::array();
      for (const GridCell& cell : map.cells) {
        cells.push_back({{"x", json_number(cell.x)},
                         {"y", json_number(cell.y)},
                         {"mean_score", json_number(cell.mean_score)},
                         {"trials", cell.trials},
                         {"participants", cell.participants}});
      }
      json best = json::array();
      for (std::size_t index : map.best) {
        best.push_back({{"x", json_number(map.cells[index].x)}, {"y", json_number(map.cells[index].y)}});
      }
      maps.push_back({{"scene", map.scene},
                      {"level", json_number(map.level)},
                      {"best", best},
                      {"best_mean_score", map.best.empty() ? json(nullptr) : json_number(map.cells[map.best[0]].mean_score)},
                      {"tie", map.best.size() > 1},
                      {"cells", cells}});
    }
    root["rating_grid"] = {{"definition", "Ye et al. 2022, 4.4.1: per cell, each participant's mean score (1-3) over the "
                                          "cell's trials, then the mean over participants"},
                           {"x_key", grid.x_key},
                           {"y_key", grid.y_key},
                           {"x_values", grid.x_values},
                           {"y_values", grid.y_values},
                           {"maps", maps}};
  }

  root["preference_table"] = json::array();
  for (const PreferenceRow& row : result.preferences) {
    root["preference_table"].push_back({{"scene", row.group.scene},
                                        {"variant", row.group.variant},
                                        {"condition", row.condition},
                                        {"reference_method", row.reference_method},
                                        {"test_method", row.test_method},
                                        {"n", row.n},
                                        {"reference_votes", row.reference_votes},
                                        {"share", json_number(row.share)},
                                        {"ci_lower", json_number(row.interval.lower)},
                                        {"ci_upper", json_number(row.interval.upper)},
                                        {"p_value", json_number(row.p_value)},
                                        {"log10_p", json_number(row.log10_p)},
                                        {"alternative", "greater"},
                                        {"stars", row.stars}});
  }

  root["participants"] = json::array();
  for (const ParticipantRow& participant : result.participants) {
    json thresholds = json::array();
    for (const ParticipantThreshold& threshold : participant.thresholds) {
      thresholds.push_back({{"scene", threshold.group.scene},
                            {"variant", threshold.group.variant},
                            {"level", json_number(threshold.level)},
                            {"note", threshold.note}});
    }
    root["participants"].push_back({{"participant", participant.participant},
                                    {"observer", participant.observer},
                                    {"log_path", participant.log_path},
                                    {"excluded", participant.excluded},
                                    {"session_ended", participant.session_ended},
                                    {"log_status", log_status_name(participant.log_status)},
                                    {"complete_trials", participant.complete_trials},
                                    {"attention_checks", participant.attention_checks},
                                    {"attention_errors", participant.attention_errors},
                                    {"latency", latency_json(participant)},
                                    {"frame_intervals", frame_intervals_json(participant.frame_intervals)},
                                    {"validation", validation_json(participant)},
                                    {"gaze_source", gaze_source_cell(participant)},
                                    {"practice_trials", participant.practice_trials},
                                    {"thresholds", thresholds}});
    if (!participant.tracks.empty()) root["participants"].back()["adaptive_tracks"] = adaptive_tracks_json(participant);
  }

  root["frame_intervals"] = frame_intervals_json(result.frame_intervals);

  root["config_versions"] = json::array();
  for (const ConfigVersion& version : result.config_versions)
    root["config_versions"].push_back({{"content_hash", version.content_hash},
                                       {"config_hash", version.config_hash},
                                       {"sessions", version.sessions},
                                       {"folders", version.folders},
                                       {"analysed", version.analysed}});
  root["left_out"] = json::array();
  for (const LeftOut& left : result.left_out) {
    root["left_out"].push_back({{"what", left.what}, {"reason", left.reason}});
  }
  return root;
}

// ---- plots -----------------------------------------------------------------------------------

// Levels spaced evenly on a log scale (4, 8, 16, ..., or 1, 2, 5, 10, ...): all positive, at least
// three, spanning a factor of 4 or more, with gaps more even in log than in linear terms. Their
// plots get a log axis, where such levels are evenly spread instead of crowded at one end.
bool log_spaced(std::vector<double> levels) {
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  if (levels.size() < 3 || !(levels.front() > 0.0) || levels.back() < 4.0 * levels.front()) return false;
  const auto spread = [](const std::vector<double>& gaps) {  // coefficient of variation
    double mean = 0.0, squares = 0.0;
    for (double gap : gaps) mean += gap / double(gaps.size());
    for (double gap : gaps) squares += (gap - mean) * (gap - mean) / double(gaps.size());
    return std::sqrt(squares) / mean;
  };
  std::vector<double> linear, logarithmic;
  for (size_t i = 1; i < levels.size(); ++i) {
    linear.push_back(levels[i] - levels[i - 1]);
    logarithmic.push_back(std::log(levels[i] / levels[i - 1]));
  }
  return spread(logarithmic) < spread(linear);
}

struct Plot {
  std::string file_name;
  std::string caption;
  std::string svg;
};

// Share of answers for the test stimulus per level (Polychronakis et al. 2023, Fig. 9), one series
// per group; rating studies: the mean rating per level (error bars ±1 SD) against the cutoff 2.
// `only`: the plot of that group alone (one of the small multiples drawn for many groups).
std::optional<Plot> share_per_level_plot(const AnalysisResult& result, const std::optional<GroupKey>& only = std::nullopt) {
  const bool rating = is_rating(result);
  std::map<GroupKey, XySeries> by_group;
  std::vector<GroupKey> order;  // first appearance, so the legend follows the table
  for (const ConditionRow& row : result.conditions) {
    if (!row.level || !std::isfinite(*row.level) || row.n == 0) continue;
    if (only && !(row.group == *only)) continue;
    double y = row.proportion;
    double lower = row.interval.lower;
    double upper = row.interval.upper;
    if (rating) {
      if (!row.mean_rating || !std::isfinite(*row.mean_rating)) continue;
      y = *row.mean_rating;
      const double sd = row.sd_rating && std::isfinite(*row.sd_rating) ? *row.sd_rating : 0.0;
      lower = y - sd;
      upper = y + sd;
    }
    if (!std::isfinite(y)) continue;
    if (!by_group.count(row.group)) order.push_back(row.group);
    XySeries& series = by_group[row.group];
    series.x.push_back(*row.level);
    series.y.push_back(y);
    series.y_lower.push_back(lower);
    series.y_upper.push_back(upper);
  }
  if (order.empty()) return std::nullopt;
  XyChart chart;
  // One meaning per title: the share of trials in favour of the test, named as the protocol counts it.
  const std::string favour(result.rules().judged_words);
  chart.title = result.study + (only ? ", " + only->label() : std::string()) +
                (rating ? ": mean rating per level" : ": share of trials the test was " + favour + ", per level");
  chart.x_label = level_axis_label(result);
  chart.y_label = rating ? "mean rating (1-3), bars: ±1 SD" : "share " + favour + " (k/n), bars: 95 % Clopper-Pearson";
  chart.y_min = rating ? 1.0 : 0.0;
  chart.y_max = rating ? 3.0 : 1.0;
  chart.horizontal_lines = {rating ? result.rating_cutoff : 0.5};
  chart.x_log = log_spaced(result.levels);
  // With several groups, each is shifted a little along x (about 6 px apart, at most 30 % of the
  // smallest gap between levels) so points and bars at one level do not hide each other.
  double offset_step = 0.0;
  if (order.size() > 1) {
    std::vector<double> levels;
    for (const auto& entry : by_group) levels.insert(levels.end(), entry.second.x.begin(), entry.second.x.end());
    std::sort(levels.begin(), levels.end());
    levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
    if (levels.size() > 1) {
      double gap = levels.back() - levels.front();
      for (std::size_t i = 1; i < levels.size(); ++i) gap = std::min(gap, levels[i] - levels[i - 1]);
      offset_step = std::min(0.017 * (levels.back() - levels.front()),
                             0.3 * gap / static_cast<double>(order.size() - 1));
    }
  }
  if (chart.x_log) {  // the same shift as a share of the log range: a factor, not a difference
    offset_step = 0.0;
    if (order.size() > 1 && !result.levels.empty()) {
      const auto [lowest, highest] = std::minmax_element(result.levels.begin(), result.levels.end());
      offset_step = 0.017 * std::log10(*highest / *lowest);
    }
  }
  for (std::size_t g = 0; g < order.size(); ++g) {
    XySeries series = by_group[order[g]];
    const double offset = offset_step * (static_cast<double>(g) - static_cast<double>(order.size() - 1) / 2);
    for (double& x : series.x) x = chart.x_log ? x * std::pow(10.0, offset) : x + offset;
    series.label = order[g].label();
    series.style = XySeries::Style::points;
    chart.series.push_back(std::move(series));
  }
  Plot plot;
  plot.file_name = "share_per_level.svg";
  plot.caption = rating ? "Mean rating per level and group (bars: ±1 SD); dashed: the cutoff 2 (minimal difference)."
                        : "Share of trials where the test was " + std::string(result.rules().judged_words) +
                              ", per level and group (bars: 95 % Clopper-Pearson intervals); dashed: 1/2, the null "
                              "hypothesis of the test.";
  if (offset_step > 0.0) plot.caption += " Groups are shifted slightly along x to keep them apart.";
  plot.svg = render_xy_chart_svg(chart);
  return plot;
}

// The headline of a group as a legend label, "headline 13.81 [12.96, 14.71]" after `prefix`; the
// interval left out when the legend would cut it (the band shows it).
std::string headline_label(const std::string& prefix, const Headline& headline) {
  const std::string full = prefix + "headline " + headline_value_text(headline);
  return full.size() <= 36 ? full : prefix + "headline " + html_number(headline.value);
}

// Marks a group's headline on a chart: its value as a dashed vertical line, its 95 % interval as a
// band (an unbounded end drawn to the edge of [lo, hi]). `prefix` names the group in the legend
// ("" when the chart shows one group); `colour` is the group's palette index (none: grey).
void mark_headline(XyChart& chart, const Headline& headline, const std::string& prefix, std::optional<std::size_t> colour,
                   double lo, double hi) {
  if (headline.lower && headline.upper) {
    const double band_lower = std::max(*headline.lower, lo);
    const double band_upper = std::min(*headline.upper, hi);
    if (band_lower <= band_upper) chart.bands.push_back({"", band_lower, band_upper, colour});
  }
  chart.vertical_lines.push_back({headline_label(prefix, headline), *headline.value, colour});
}

// Why a group's plot shows no threshold mark: "blur: not estimable (the fit's threshold lies
// outside the tested levels)".
std::string unmarked_headline_note(const Headline& headline) {
  return headline.group.label() + ": " + headline_status_name(headline.status) +
         (headline.reason.empty() ? std::string() : " (" + headline.reason + ")");
}

// Each included participant's share of trials with a difference reported per level, where their
// data give one: adaptive tracks of the group (block = the group's scene, or any block for "all"),
// at levels they were shown at least twice. Constant-stimulus designs keep no per-participant
// counts in the result.
XySeries participant_proportions(const AnalysisResult& result, const GroupKey& group) {
  XySeries points;
  points.style = XySeries::Style::points;
  points.small = true;
  for (const ParticipantRow& participant : result.participants) {
    if (participant.excluded) continue;
    std::map<double, std::pair<int, int>> by_level;  // level -> (trials, seen)
    for (const AdaptiveTrackResult& track : participant.tracks) {
      if (track.variant != group.variant || (group.scene != "all" && track.block != group.scene)) continue;
      for (size_t i = 0; i < track.levels.size() && i < track.seen.size(); ++i) {
        auto& [trials, seen] = by_level[track.levels[i]];
        ++trials;
        seen += track.seen[i] ? 1 : 0;
      }
    }
    for (const auto& [level, counts] : by_level) {
      if (counts.first < 2 || !std::isfinite(level)) continue;
      points.x.push_back(level);
      points.y.push_back(double(counts.second) / double(counts.first));
    }
  }
  return points;
}

// Data (share of "difference reported" with Clopper-Pearson intervals), fitted curves and the
// headline threshold (a dashed line and its interval as a band) of the groups of one scene: one
// group alone gets every fitted shape; several variants are overlaid, one colour each, with their
// first fit. Each participant's proportions, where the data give them, are small points.
std::optional<Plot> psychometric_plot(const AnalysisResult& result, const std::vector<const GroupFit*>& groups,
                                      std::set<std::string>& taken) {
  if (groups.empty()) return std::nullopt;
  const bool overlay = groups.size() > 1;
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  for (const GroupFit* group : groups)
    for (const LevelCounts& counts : group->data) {
      if (counts.n == 0 || counts.k > counts.n || !std::isfinite(counts.level)) continue;
      lo = std::min(lo, counts.level);
      hi = std::max(hi, counts.level);
    }
  if (!(lo < hi)) {  // one level or none: the study's levels give the range of the curves
    for (double level : result.levels) {
      if (!std::isfinite(level)) continue;
      lo = std::min(lo, level);
      hi = std::max(hi, level);
    }
  }
  XyChart chart;
  const GroupFit& first = *groups.front();
  // The complement of the share plot's quantity: what the psychometric function models.
  chart.title = (overlay ? first.group.scene : first.group.label()) + ": P(difference reported) = 1 - share " +
                std::string(result.rules().judged_words);
  chart.x_label = level_axis_label(result);
  chart.y_label = "P(difference reported)";
  chart.y_min = 0.0;
  chart.y_max = 1.0;
  chart.x_log = log_spaced(result.levels) && lo > 0.0;
  std::vector<std::string> unmarked;
  bool any_participants = false, any_data = false;
  // Overlaid variants share levels: each one's points are shifted a little along x (as in the share
  // plot: 1.7 % of the range, at most 30 % of the smallest gap; on a log axis a factor).
  double offset_step = 0.0;
  if (overlay && lo < hi) {
    std::vector<double> levels = result.levels;
    std::sort(levels.begin(), levels.end());
    double gap = hi - lo;
    for (size_t i = 1; i < levels.size(); ++i)
      if (levels[i] > levels[i - 1]) gap = std::min(gap, levels[i] - levels[i - 1]);
    offset_step = chart.x_log ? 0.017 * std::log10(hi / lo)
                              : std::min(0.017 * (hi - lo), 0.3 * gap / static_cast<double>(groups.size() - 1));
  }
  for (size_t g = 0; g < groups.size(); ++g) {
    const GroupFit& group = *groups[g];
    const double offset = offset_step * (static_cast<double>(g) - static_cast<double>(groups.size() - 1) / 2);
    const auto shifted = [&](double x) { return chart.x_log ? x * std::pow(10.0, offset) : x + offset; };
    const std::optional<std::size_t> colour = overlay ? std::optional<std::size_t>(g) : std::nullopt;
    const std::string name = group.group.variant.empty() ? "(no variant)" : group.group.variant;
    XySeries data;
    data.label = overlay ? name + ": data" : "data";
    data.style = XySeries::Style::points;
    data.colour = colour.value_or(0);
    for (const LevelCounts& counts : group.data) {
      if (counts.n == 0 || counts.k > counts.n || !std::isfinite(counts.level)) continue;
      const ProportionInterval interval = clopper_pearson_interval(counts.k, counts.n);
      data.x.push_back(shifted(counts.level));
      data.y.push_back(static_cast<double>(counts.k) / static_cast<double>(counts.n));
      data.y_lower.push_back(interval.lower);
      data.y_upper.push_back(interval.upper);
    }
    XySeries participants = participant_proportions(result, group.group);
    for (double& x : participants.x) x = shifted(x);
    if (!participants.x.empty()) {
      participants.colour = data.colour;
      if (!any_participants) participants.label = "each participant";
      any_participants = true;
      chart.series.push_back(std::move(participants));
    }
    if (!data.x.empty()) {
      any_data = true;
      chart.series.push_back(data);
    }
    if (lo < hi) {
      for (size_t f = 0; f < group.fits.size() && (f == 0 || !overlay); ++f) {
        const PsychometricFit& fit = group.fits[f];
        XySeries curve;
        curve.style = XySeries::Style::line;
        if (overlay) curve.colour = g;
        else curve.colour = f + 1;
        // "cumulative_normal" is the name in the tables; the legend has room for a short one.
        const std::string shape =
            fit.model.shape == PsychometricShape::cumulative_normal ? "normal" : shape_name(fit.model.shape);
        // Overlaid: the variant and the shape (the headline's line gives the number).
        curve.label = overlay ? name + ": " + shape + " fit"
                              : shape + " fit, threshold " + format_number(fit.model.parameters.threshold, kHtmlDigits);
        for (int i = 0; i < kCurveSamples; ++i) {
          const double t = double(i) / (kCurveSamples - 1);
          const double level = chart.x_log ? lo * std::pow(hi / lo, t) : lo + (hi - lo) * t;
          curve.x.push_back(level);
          curve.y.push_back(fit.model.p_report(level));
        }
        chart.series.push_back(std::move(curve));
      }
    }
    const Headline* headline = headline_of(result, group.group);
    if (marks_level(headline)) {
      mark_headline(chart, *headline, overlay ? name + ": " : "", colour, lo, hi);
    } else if (headline) {
      unmarked.push_back(unmarked_headline_note(*headline));
    } else if (!group.fits.empty() && !overlay) {
      // No headline from the analysis: the first fit's profile interval, as before headlines existed.
      const ParameterInterval& interval = group.fits.front().threshold_interval;
      const double band_lower = std::max(interval.lower, lo);
      const double band_upper = std::min(interval.upper, hi);
      if (band_lower <= band_upper)  // false for NaN ends and for an interval beyond the tested levels
        chart.bands.push_back({std::string("threshold CI (") + shape_name(group.fits.front().model.shape) + ")",
                               band_lower, band_upper, std::nullopt});
    }
  }
  if (chart.series.empty()) return std::nullopt;
  Plot plot;
  std::string stem = "psychometric_" + safe_name(first.group.scene);
  if (!overlay && !first.group.variant.empty()) stem += "_" + safe_name(first.group.variant);
  plot.file_name = unique_svg_name(stem, taken);
  plot.caption = "Psychometric fits for " + (overlay ? first.group.scene + ", its variants overlaid" : first.group.label()) +
                 ": share of trials with a difference reported (bars: 95 % Clopper-Pearson), the fitted curve" +
                 (overlay ? " of each variant" : "s") +
                 (chart.vertical_lines.empty() ? std::string()
                                               : ", and the headline threshold (dashed) with its 95 % interval (shaded)");
  if (any_participants) plot.caption += "; small points: each participant's share at a level they saw at least twice";
  plot.caption += ".";
  if (offset_step > 0.0) plot.caption += " The variants' points are shifted slightly along x to keep them apart.";
  if (!any_data) plot.caption += " No pooled data to show.";
  if (!unmarked.empty()) plot.caption += " No threshold marked for " + joined(unmarked, "; ") + ".";
  plot.svg = render_xy_chart_svg(chart);
  return plot;
}

// Each included participant's threshold as a point (pair, ramp, slider), one row a participant, the
// variants of one scene overlaid (one colour each, rows shifted a little apart), with the headline
// (the mean over participants: a dashed line) and its 95 % interval (shaded).
std::vector<Plot> participant_threshold_plots(const AnalysisResult& result, std::set<std::string>& taken) {
  std::vector<std::string> scenes;
  std::map<std::string, std::vector<GroupKey>> groups_of;  // scene -> its groups, first appearance first
  std::vector<const ParticipantRow*> rows;                  // participants with a threshold, in path order
  for (const ParticipantRow& participant : result.participants) {
    if (participant.excluded) continue;
    bool any = false;
    for (const ParticipantThreshold& threshold : participant.thresholds) {
      if (!threshold.level || !std::isfinite(*threshold.level)) continue;
      any = true;
      auto& groups = groups_of[threshold.group.scene];
      if (groups.empty()) scenes.push_back(threshold.group.scene);
      if (std::find(groups.begin(), groups.end(), threshold.group) == groups.end()) groups.push_back(threshold.group);
    }
    if (any) rows.push_back(&participant);
  }
  std::vector<Plot> plots;
  for (const std::string& scene : scenes) {
    const std::vector<GroupKey>& groups = groups_of[scene];
    const bool overlay = groups.size() > 1;
    XyChart chart;
    chart.title = result.study + ", " + scene + ": each participant's threshold";
    chart.x_label = "threshold " + level_axis_label(result);
    chart.y_label = "participant (in log-path order)";
    chart.y_min = 0.0;
    chart.y_max = double(rows.size()) + 1.0;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double level : result.levels) {
      lo = std::min(lo, level);
      hi = std::max(hi, level);
    }
    std::vector<std::string> unmarked;
    for (size_t g = 0; g < groups.size(); ++g) {
      const GroupKey& group = groups[g];
      const std::string name = group.variant.empty() ? "(no variant)" : group.variant;
      const double shift = overlay ? 0.5 * (double(g) - double(groups.size() - 1) / 2) / double(groups.size()) : 0.0;
      XySeries points;
      points.style = XySeries::Style::points;
      points.colour = g;
      points.label = overlay ? name + ": each participant" : "each participant";
      for (size_t r = 0; r < rows.size(); ++r)
        for (const ParticipantThreshold& threshold : rows[r]->thresholds) {
          if (!(threshold.group == group) || !threshold.level || !std::isfinite(*threshold.level)) continue;
          points.x.push_back(*threshold.level);
          points.y.push_back(double(r + 1) + shift);
          if (!overlay && rows.size() <= kTrackPlots) points.point_labels.push_back(rows[r]->participant);
          lo = std::min(lo, *threshold.level);
          hi = std::max(hi, *threshold.level);
        }
      if (!points.point_labels.empty() && points.point_labels.size() != points.x.size()) points.point_labels.clear();
      chart.series.push_back(std::move(points));
    }
    for (size_t g = 0; g < groups.size(); ++g) {
      const std::string name = groups[g].variant.empty() ? "(no variant)" : groups[g].variant;
      const Headline* headline = headline_of(result, groups[g]);
      if (marks_level(headline)) {
        mark_headline(chart, *headline, overlay ? name + ": " : "", g, lo, hi);
      } else if (headline) {
        unmarked.push_back(unmarked_headline_note(*headline));
      } else {
        // No headline from the analysis: the paper's mean over participants and its interval.
        for (const GroupThreshold& threshold : result.thresholds)
          if (threshold.group == groups[g] && threshold.mean) {
            if (threshold.mean_lower && threshold.mean_upper)
              chart.bands.push_back({"", *threshold.mean_lower, *threshold.mean_upper, g});
            chart.vertical_lines.push_back({(overlay ? name + ": " : std::string()) + "mean " +
                                                html_number(threshold.mean) +
                                                (threshold.mean_lower && threshold.mean_upper
                                                     ? " " + html_interval(*threshold.mean_lower, *threshold.mean_upper)
                                                     : std::string()),
                                            *threshold.mean, g});
          }
      }
    }
    chart.x_log = log_spaced(result.levels) && lo > 0.0;
    Plot plot;
    plot.file_name = unique_svg_name("participant_thresholds_" + safe_name(scene), taken);
    plot.caption = "Each included participant's threshold, " + scene +
                   (overlay ? " (variants overlaid, each row shifted a little per variant)" : std::string()) +
                   (chart.vertical_lines.empty()
                        ? std::string(".")
                        : "; dashed: each group's headline (its method in the Headline table) with its 95 % interval "
                          "(shaded).");
    if (!unmarked.empty()) plot.caption += " No threshold marked for " + joined(unmarked, "; ") + ".";
    plot.svg = render_xy_chart_svg(chart);
    plots.push_back(std::move(plot));
  }
  return plots;
}

// Ye et al. 2022, Figure 9: one heat map per block (and for every block pooled) of the mean score per pair
// of the two grid parameters over every level, coloured on the score's scale 1..3, the best pair
// outlined.
std::vector<Plot> rating_grid_plots(const AnalysisResult& result, std::set<std::string>& taken) {
  std::vector<Plot> plots;
  if (!result.rating_grid) return plots;
  const RatingGrid& grid = *result.rating_grid;
  for (const GridMap& map : grid.maps) {
    if (map.level) continue;  // per level: in the CSV and JSON only
    HeatMap heat;
    heat.title = map.scene + ": mean score (1-3) over every level";
    heat.x_label = grid.x_key;
    heat.y_label = grid.y_key;
    heat.x_values = grid.x_values;
    heat.y_values = grid.y_values;
    for (const GridCell& cell : map.cells) heat.cells.push_back(cell.mean_score.value_or(std::nan("")));
    heat.cell_format = "%.2f";
    heat.colour_min = 1.0;
    heat.colour_max = 3.0;
    heat.marked_cells = map.best;
    heat.marked_label = map.best.size() > 1 ? "outlined: highest mean (a tie)" : "outlined: highest mean";
    Plot plot;
    plot.file_name = unique_svg_name("rating_grid_" + safe_name(map.scene), taken);
    plot.caption = "Pilot grid, " + map.scene + ": mean score (3 identical, 2 minimal difference, 1 significant "
                   "difference) per pair of " + grid.x_key + " and " + grid.y_key +
                   ", each participant's mean over every level, then the mean over participants; grey: no trial; "
                   "outlined: the highest mean" + (map.best.size() > 1 ? " (a tie)" : "") + ".";
    plot.svg = render_heat_map_svg(heat);
    plots.push_back(std::move(plot));
  }
  return plots;
}

// Bins centred on the study's levels (edges midway between neighbouring levels); without levels, on
// the distinct thresholds themselves.
std::vector<double> level_bin_edges(std::vector<double> centres) {
  centres.erase(std::remove_if(centres.begin(), centres.end(), [](double v) { return !std::isfinite(v); }),
                centres.end());
  std::sort(centres.begin(), centres.end());
  centres.erase(std::unique(centres.begin(), centres.end()), centres.end());
  if (centres.empty()) return {};
  if (centres.size() == 1) return {centres[0] - 0.5, centres[0] + 0.5};
  std::vector<double> edges = {centres[0] - (centres[1] - centres[0]) / 2};
  for (std::size_t i = 1; i < centres.size(); ++i) edges.push_back((centres[i - 1] + centres[i]) / 2);
  const std::size_t last = centres.size() - 1;
  edges.push_back(centres[last] + (centres[last] - centres[last - 1]) / 2);
  return edges;
}

// Per-participant thresholds of the included participants (Polychronakis et al. 2021, Fig. 7): pooled over the
// groups, and one histogram a group when there are several.
std::vector<Plot> threshold_histograms(const AnalysisResult& result, std::set<std::string>& taken) {
  std::map<GroupKey, std::vector<double>> by_group;
  std::vector<double> all;
  for (const ParticipantRow& participant : result.participants) {
    if (participant.excluded) continue;
    for (const ParticipantThreshold& threshold : participant.thresholds) {
      if (!threshold.level || !std::isfinite(*threshold.level)) continue;
      by_group[threshold.group].push_back(*threshold.level);
      all.push_back(*threshold.level);
    }
  }
  if (all.empty()) return {};
  std::vector<Plot> plots;
  auto make = [&](const std::string& stem, const std::string& what, const std::vector<double>& values) {
    Histogram histogram;
    histogram.title = result.study + ": per-participant thresholds" + what;
    histogram.x_label = "threshold " + level_axis_label(result);
    histogram.values = values;
    histogram.bin_edges = level_bin_edges(result.levels.empty() ? values : result.levels);
    Plot plot;
    plot.file_name = unique_svg_name(stem, taken);
    plot.caption = "Per-participant thresholds" + what + " (included participants; one bin a level).";
    plot.svg = render_histogram_svg(histogram);
    plots.push_back(std::move(plot));
  };
  make("thresholds_histogram", by_group.size() > 1 ? ", all groups" : "", all);
  if (by_group.size() > 1) {
    for (const auto& [group, values] : by_group) {
      std::string stem = "thresholds_histogram_" + safe_name(group.scene);
      if (!group.variant.empty()) stem += "_" + safe_name(group.variant);
      make(stem, ", " + group.label(), values);
    }
  }
  return plots;
}

// A participant's adaptive tracks: each one's level trial by trial (a line), the trials whose answer
// saw the difference and those that did not, a staircase's reversals, and each threshold (dashed).
// At most kTrackPlots participants are drawn; adaptive_tracks.csv holds every track.

std::vector<Plot> adaptive_track_plots(const AnalysisResult& result, std::set<std::string>& taken) {
  std::vector<Plot> plots;
  for (const ParticipantRow& participant : result.participants) {
    if (participant.tracks.empty() || plots.size() >= kTrackPlots) continue;
    XyChart chart;
    chart.title = participant.participant + ": adaptive tracks";
    chart.x_label = "trial of the track";
    chart.y_label = level_axis_label(result);
    XySeries seen{"seen", XySeries::Style::points, {}, {}, {}, {}, {}};
    XySeries not_seen{"not seen", XySeries::Style::points, {}, {}, {}, {}, {}};
    XySeries reversals{"reversal", XySeries::Style::points, {}, {}, {}, {}, {}};
    for (const AdaptiveTrackResult& track : participant.tracks) {
      XySeries line;
      line.style = XySeries::Style::line;
      line.label = (track.variant.empty() ? "" : track.variant + ", ") +
                   (track.start_level ? "start " + format_number(*track.start_level, kHtmlDigits) : track.procedure);
      for (size_t i = 0; i < track.levels.size(); ++i) {
        line.x.push_back(double(i + 1));
        line.y.push_back(track.levels[i]);
        XySeries& answer = track.seen[i] ? seen : not_seen;
        answer.x.push_back(double(i + 1));
        answer.y.push_back(track.levels[i]);
      }
      for (int trial : track.reversal_trials) {
        reversals.x.push_back(double(trial + 1));
        reversals.y.push_back(track.levels.at(static_cast<size_t>(trial)));
      }
      if (track.threshold) chart.horizontal_lines.push_back(*track.threshold);
      chart.series.push_back(std::move(line));
    }
    for (XySeries* answers : {&seen, &not_seen, &reversals})
      if (!answers->x.empty()) chart.series.push_back(std::move(*answers));
    Plot plot;
    plot.file_name = unique_svg_name("adaptive_tracks_" + safe_name(participant.participant), taken);
    plot.caption = participant.participant + "'s adaptive tracks: the level of each trial, its answer, a staircase's "
                   "reversals, and each threshold (dashed: a staircase's mean of its last reversals, QUEST+'s "
                   "posterior mean).";
    plot.svg = render_xy_chart_svg(chart);
    plots.push_back(std::move(plot));
  }
  return plots;
}

// The histogram of a frame-interval summary: bins a sixteenth of a refresh period wide (about 1 ms
// at 60 Hz, so a display's jitter shows), centred on
// multiples of it (an interval of exactly one period sits mid-bar), from 0 to 3 to 6 periods
// (longer intervals in the last bar), with the late limit (1.5 periods) marked. Without a refresh
// rate the median stands for the period.
Histogram frame_interval_histogram(const FrameIntervalSummary& frames, const std::string& title) {
  Histogram histogram;
  histogram.title = title;
  histogram.x_label = "interval between presented refreshes (ms)";
  for (const auto& [us, count] : frames.count_by_us) {
    histogram.values.push_back(static_cast<double>(us) / 1e3);
    histogram.counts.push_back(static_cast<double>(count));
  }
  const double period_ms = frames.refresh_hz ? 1e3 / *frames.refresh_hz : frames.median_ms.value_or(0.0);
  if (period_ms > 0.0 && std::isfinite(period_ms)) {
    const double periods = std::clamp(std::ceil(frames.max_ms.value_or(period_ms) / period_ms), 3.0, 6.0);
    const double width = period_ms / 16;
    for (int k = 0; k <= static_cast<int>(periods * 16) + 1; ++k) histogram.bin_edges.push_back((k - 0.5) * width);
    histogram.bin_edges.front() = 0.0;
    histogram.count_labels = false;
    if (frames.refresh_hz) {
      histogram.vertical_lines = {kLateRefreshPeriods * period_ms};
      histogram.vertical_lines_label = "dashed: late beyond 1.5 refresh periods (" +
                                       format_number(kLateRefreshPeriods * period_ms, kHtmlDigits) + " ms)";
    }
  }
  return histogram;
}

// The study's frame-interval histogram, then one a session (at most kTrackPlots).
std::vector<Plot> frame_interval_plots(const AnalysisResult& result, std::set<std::string>& taken) {
  std::vector<Plot> plots;
  const FrameIntervalSummary study = result.frame_intervals;
  if (study.intervals == 0) return plots;
  Plot plot;
  plot.file_name = unique_svg_name("frame_intervals", taken);
  plot.caption = "Intervals between presented refreshes, every included session pooled (" +
                 std::to_string(study.intervals) + " intervals).";
  plot.svg = render_histogram_svg(frame_interval_histogram(study, result.study + ": frame intervals, every session"));
  plots.push_back(std::move(plot));
  size_t sessions = 0;
  for (const ParticipantRow& participant : result.participants) {
    if (participant.frame_intervals.intervals == 0 || sessions >= kTrackPlots) continue;
    ++sessions;
    Plot session;
    session.file_name = unique_svg_name("frame_intervals_" + safe_name(participant.participant), taken);
    session.caption = participant.participant + "'s session: intervals between presented refreshes (" +
                      std::to_string(participant.frame_intervals.intervals) + " intervals).";
    session.svg = render_histogram_svg(
        frame_interval_histogram(participant.frame_intervals, participant.participant + ": frame intervals"));
    plots.push_back(std::move(session));
  }
  return plots;
}

// ---- HTML ------------------------------------------------------------------------------------

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
      items += "<li><strong>" + std::string(paper.cited_as) + "</strong>: " + html_escape(std::string(paper.reference)) +
               "</li>\n";
  if (items.empty()) return {};
  return "<h2 id=\"references\">References</h2>\n<ul>\n" + items + "</ul>\n";
}

// The frame-interval section: the study's and each session's summary, the study's histogram and
// the sessions' (collapsed).
std::string html_frame_intervals(const AnalysisResult& result, const std::vector<Plot>& frame_plots) {
  std::string html = "<h2 id=\"frame-intervals\">Frame intervals</h2>\n";
  html += "<p>The intervals between consecutive refreshes presented during each stimulus (the log's present times; "
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
    rows.push_back(row(participant.participant + (participant.excluded ? " (excluded)" : ""), participant.frame_intervals));
  html += html_table({"session", "refresh (Hz)", "intervals", "median (ms)", "SD (ms)", "p99 (ms)", "max (ms)",
                      "late (> 1.5 refreshes)", "late share"},
                     rows);
  for (size_t i = 0; i < frame_plots.size(); ++i) {
    if (i == 1) html += "<details><summary>Each session's histogram</summary>\n";
    html += "<figure>\n" + inline_svg(frame_plots[i].svg) + "<figcaption>" + html_escape(frame_plots[i].caption) + " (" +
            html_escape(frame_plots[i].file_name) + ")</figcaption>\n</figure>\n";
  }
  if (frame_plots.size() > 1) html += "</details>\n";
  return html;
}

// The Headline section, first on the page: one row a group, the value only when it is one.
std::string html_headlines(const AnalysisResult& result) {
  std::string html = "<h2 id=\"headline\">Headline</h2>\n";
  if (result.headlines.empty()) return html + "<p>No headline: the analysis gave none for this design.</p>\n";
  html += "<p>The number to publish for each group, with its 95 % interval, the method that gives it and what "
          "that method aims at. A status other than <em>estimated</em> is shown with its reason and no number. "
          "The paper's own rule is beside it; the same in headline.csv and thresholds.json (headlines).</p>\n";
  html += "<div class=\"table\"><table class=\"headline\">\n<thead>" +
          html_row({"group", "quantity", "value [95 % interval]", "status", "method", "aims at", "flags", "participants",
                    "the paper's rule"},
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
      lines.insert(lines.begin(), "the pooled fit of every adaptive trial: " + html_number(headline.pooled_fit) +
                                      (headline.pooled_fit_lower && headline.pooled_fit_upper
                                           ? " " + html_interval(*headline.pooled_fit_lower, *headline.pooled_fit_upper)
                                           : std::string()));
    for (const std::string& line : lines)
      notes += "<li><strong>" + html_escape(headline.group.label()) + "</strong>: " + html_escape(line) + "</li>\n";
  }
  if (!notes.empty()) html += "<ul class=\"notes\">\n" + notes + "</ul>\n";
  return html;
}

std::string report_html(const AnalysisResult& result, const std::vector<Plot>& plots,
                        const std::vector<Plot>& frame_plots) {
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
    item("Level parameter", result.level_parameter + (result.higher_is_better ? " (higher is better)" : " (lower is better)"));
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
  item("Observers", result.observers == "human" ? "human (real participants)"
                    : result.observers == "simulated" ? "simulated observers only: not real participants' data"
                                                      : "human and simulated, pooled on request (--observers all)");
  // Ramps and sliders have no per-condition tests or fits: their thresholds are per participant.
  const bool per_condition = result.protocol != ProtocolKind::ramp && result.protocol != ProtocolKind::slider;
  if (per_condition) {
    item("Test", test_description(result));
    item("Guess rate of the fits",
         html_number(result.guess_rate) + (result.guess_rate_source.empty() ? "" : " (" + result.guess_rate_source + ")"));
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
      return "(" + std::to_string(std::find(definitions.begin(), definitions.end(), definition) - definitions.begin() + 1) + ")";
    };
    if (!several) {
      html += "<p class=\"definition\"><strong>Definition</strong>: " + html_escape(definitions.front()) + "</p>\n";
    } else {
      html += "<p class=\"definition\"><strong>Definitions</strong> (the table's column names which):</p>\n"
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
        pairs += (pairs.empty() ? "(" : "; (") + html_number(map.cells[index].x) + ", " + html_number(map.cells[index].y) + ")";
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
    html += "<h2 id=\"preference\">Preference table</h2>\n<p>Ye et al. 2022, Table 2: the votes for the reference "
            "stimulus. Test: exact binomial, one-sided (greater: the reference preferred), H0 p = 1/2, whatever "
            "--alternative says, no correction; CI: 95 % Clopper-Pearson of the share.</p>\n";
    std::vector<std::vector<std::string>> rows;
    for (const PreferenceRow& row : result.preferences) {
      rows.push_back({row.group.scene, row.group.variant, row.condition,
                      row.reference_method + " v. " + row.test_method,
                      std::to_string(row.reference_votes) + " / " + std::to_string(row.n),
                      format_number(100.0 * row.share, 3) + " %", p_value_text(row.p_value, row.log10_p, kHtmlDigits), row.stars,
                      html_interval(row.interval.lower, row.interval.upper)});
    }
    html += html_table({"scene", "variant", "condition", "reference v. test", "votes for the reference",
                        "share", "p (one-sided)", "stars", "95 % CI"},
                       rows);
  }

  html += "<h2 id=\"plots\">Plots</h2>\n";
  if (plots.empty()) html += "<p>No plots (no data to plot).</p>\n";
  for (const Plot& plot : plots) {
    html += "<figure>\n" + inline_svg(plot.svg) + "<figcaption>" + html_escape(plot.caption) + " (" +
            html_escape(plot.file_name) + ")</figcaption>\n</figure>\n";
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
      fit_rows.push_back({group.group.scene, group.group.variant, shape_name(fit.model.shape),
                          fit.model.rising ? "rising" : "falling", html_number(p.threshold),
                          html_interval(fit.threshold_interval.lower, fit.threshold_interval.upper),
                          html_number(p.slope), html_interval(fit.slope_interval.lower, fit.slope_interval.upper),
                          html_number(p.lapse), html_interval(fit.lapse_interval.lower, fit.lapse_interval.upper),
                          html_number(fit.model.guess), html_number(fit.deviance),
                          std::to_string(fit.degrees_of_freedom), html_number(fit.deviance_p_value),
                          html_number(fit.log_likelihood), fit.converged ? "yes" : "no",
                          std::to_string(fit.bootstrap_samples) + " / " + std::to_string(fit.bootstrap_failures),
                          fit.note});
    }
    for (const std::string& reason : group.not_fitted) not_fitted.push_back(group.group.label() + ": " + reason);
  }
  if (fit_rows.empty()) {
    if (per_condition) html += "<p>No fits.</p>\n";
  } else {
    html += html_table({"scene", "variant", "shape", "direction", "threshold", "threshold CI", "slope", "slope CI",
                        "lapse", "lapse CI", "guess", "deviance", "dof", "p (deviance)", "log L", "converged",
                        "bootstrap ok / failed", "note"},
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
    std::vector<std::string> header = {"scene", "variant", "method", "condition", "level", "n", "k", "k/n", "95 % CI",
                                       "p", "p (Holm)", "stars"};
    if (ratings) header.insert(header.end(), {"mean rating", "SD rating"});
    std::vector<std::vector<std::string>> rows;
    for (const ConditionRow& row : result.conditions) {
      std::vector<std::string> cells = {row.group.scene, row.group.variant, row.method, row.condition, html_number(row.level),
                                        std::to_string(row.n), std::to_string(row.k), html_number(row.proportion),
                                        html_interval(row.interval.lower, row.interval.upper),
                                        p_value_text(row.p_value, row.log10_p, kHtmlDigits), html_number(row.p_holm),
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
      const std::vector<std::string> common = {p.participant, p.observer, p.excluded ? "yes" : "no", p.session_ended ? "yes" : "no",
                                               p.log_note.empty() ? log_status_name(p.log_status) : p.log_note,
                                               std::to_string(p.complete_trials) +
                                                   (p.practice_trials ? " (+" + std::to_string(p.practice_trials) + " practice)" : ""),
                                               std::to_string(p.attention_errors) + " / " +
                                                   std::to_string(p.attention_checks),
                                               p.latency_recorded ? html_number(p.latency.median_ms) + " / " +
                                                                        html_number(p.latency.p95_ms) + " (" +
                                                                        p.present_clock + ")"
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
    html += html_table({"participant", "observer", "excluded", "session ended", "log", "complete trials", "attention errors / checks",
                        "gaze-to-present ms, median / p95 (clock)", "dropped frames", "gaze source",
                        "eye-tracker checks passed / tried; accuracy (worst), precision", "scene", "variant", "threshold",
                        "note"},
                       rows);
  }

  html += html_frame_intervals(result, frame_plots);

  const auto with_tracks = std::count_if(result.participants.begin(), result.participants.end(),
                                         [](const ParticipantRow& p) { return !p.tracks.empty(); });
  if (with_tracks > 0) {
    html += "<h2 id=\"adaptive\">Adaptive tracks</h2>\n<p>Each adaptive track's threshold by its procedure's rule "
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
          (with_tracks > 0 ? "adaptive_tracks.csv, " : "") + "thresholds.json.</p>\n";
  html += html_references(html);
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace

std::vector<std::string> write_analysis_report(const AnalysisResult& result, const std::string& out_dir) {
  const fs::path dir(out_dir);
  fs::create_directories(dir);
  std::vector<std::string> written;
  auto write = [&](const std::string& name, const std::string& text) {
    const fs::path path = dir / name;
    write_text_atomically(path, text);
    written.push_back(path.string());
  };

  write("headline.csv", headline_csv(result));
  write("conditions.csv", conditions_csv(result));
  write("participants.csv", participants_csv(result));
  const bool adaptive = std::any_of(result.participants.begin(), result.participants.end(),
                                    [](const ParticipantRow& participant) { return !participant.tracks.empty(); });
  if (adaptive) write("adaptive_tracks.csv", adaptive_tracks_csv(result));
  if (result.rating_grid) write("rating_grid.csv", rating_grid_csv(*result.rating_grid, result.study));
  if (!result.preferences.empty()) write("preference.csv", preference_csv(result));
  write("thresholds.json", thresholds_json(result).dump(2, ' ', false, json::error_handler_t::replace) + "\n");

  std::set<std::string> taken = {"share_per_level.svg"};
  std::vector<Plot> plots;
  // Up to four groups share one plot; more get one plot each (small multiples), which stay readable.
  std::vector<GroupKey> groups;
  for (const ConditionRow& row : result.conditions)
    if (row.level && std::find(groups.begin(), groups.end(), row.group) == groups.end()) groups.push_back(row.group);
  if (groups.size() <= kGroupsInOnePlot) {
    if (auto plot = share_per_level_plot(result)) plots.push_back(std::move(*plot));
  } else {
    for (const GroupKey& group : groups)
      if (auto plot = share_per_level_plot(result, group)) {
        std::string stem = "share_per_level_" + safe_name(group.scene);
        if (!group.variant.empty()) stem += "_" + safe_name(group.variant);
        plot->file_name = unique_svg_name(stem, taken);
        plots.push_back(std::move(*plot));
      }
  }
  for (Plot& plot : rating_grid_plots(result, taken)) plots.push_back(std::move(plot));
  // The psychometric plots: a scene's variants overlaid on one (up to four), else one a group.
  std::vector<std::vector<const GroupFit*>> by_scene;
  for (const GroupFit& group : result.fits) {
    auto same = std::find_if(by_scene.begin(), by_scene.end(), [&](const std::vector<const GroupFit*>& fits) {
      return fits.front()->group.scene == group.group.scene;
    });
    if (same == by_scene.end()) by_scene.push_back({&group});
    else same->push_back(&group);
  }
  for (const std::vector<const GroupFit*>& scene : by_scene) {
    if (scene.size() <= kGroupsInOnePlot) {
      if (auto plot = psychometric_plot(result, scene, taken)) plots.push_back(std::move(*plot));
    } else {
      for (const GroupFit* group : scene)
        if (auto plot = psychometric_plot(result, {group}, taken)) plots.push_back(std::move(*plot));
    }
  }
  for (Plot& plot : participant_threshold_plots(result, taken)) plots.push_back(std::move(plot));
  for (Plot& plot : threshold_histograms(result, taken)) plots.push_back(std::move(plot));
  for (Plot& plot : adaptive_track_plots(result, taken)) plots.push_back(std::move(plot));
  for (const Plot& plot : plots) write(plot.file_name, plot.svg);
  const std::vector<Plot> frame_plots = frame_interval_plots(result, taken);
  for (const Plot& plot : frame_plots) write(plot.file_name, plot.svg);

  write("report.html", report_html(result, plots, frame_plots));
  return written;
}

namespace {

// A name write_analysis_report writes, or the temporary of one (".<stem>.tmp-<pid>.<ext>", left
// inside by a run killed before this folder-level writing existed).
bool is_report_file_name(const std::string& name) {
  if (name == "thresholds.json" || name == "headline.csv" || name == "conditions.csv" || name == "participants.csv" || name == "report.html" ||
      name == "rating_grid.csv" || name == "preference.csv" || name == "adaptive_tracks.csv")
    return true;
  const auto ends_with = [&](const std::string& end) {
    return name.size() > end.size() && name.compare(name.size() - end.size(), end.size(), end) == 0;
  };
  if (name[0] == '.' && name.find(".tmp-") != std::string::npos) return true;
  return ends_with(".svg");
}

}  // namespace

void check_analysis_destination(const std::string& out_dir, bool replace) {
  const fs::path dir(out_dir);
  remove_stale_folder_temporaries(dir);
  std::error_code error;
  const fs::file_status status = fs::symlink_status(dir, error);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status))
    throw InputError(out_dir + ": is not a folder; give --out a folder for the analysis");
  bool has_thresholds = false;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || entry.is_symlink() || !is_report_file_name(name))
      throw InputError(out_dir + ": holds " + name +
                       ", which fovlab analyze does not write; give --out another folder (--force replaces only an "
                       "earlier analysis)");
    has_thresholds = has_thresholds || name == "thresholds.json";
  }
  if (!has_thresholds && !fs::is_empty(dir))
    throw InputError(out_dir + ": holds files but no thresholds.json (not an analysis); give --out another folder");
  if (has_thresholds && !replace)
    throw InputError(out_dir + ": an analysis is already there; add --force to replace it");
}

std::vector<std::string> write_analysis_folder(const AnalysisResult& result, const std::string& out_dir, bool replace) {
  check_analysis_destination(out_dir, replace);
  std::vector<std::string> written;
  write_folder_atomically(out_dir, replace, [&](const fs::path& temporary) {
    for (const std::string& path : write_analysis_report(result, temporary.string()))
      written.push_back((fs::path(out_dir) / fs::path(path).filename()).string());
  });
  return written;
}

}  // namespace fovlab::analysis
