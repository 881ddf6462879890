#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "analysis/report/report_formats.h"
#include "core/csv.h"
#include "core/number_text.h"

namespace fovlab::analysis::report_detail {
namespace {

constexpr int kCsvDigits = 10;  // significant digits of numbers in the CSV files

std::string csv_number(double value) { return std::isfinite(value) ? format_number(value, kCsvDigits) : ""; }
std::string csv_number(const std::optional<double>& value) { return value ? csv_number(*value) : ""; }

// The latency columns of a participant: median and p95 (ms), refreshes counted, dropped frames and
// the present clock ("not recorded" for a log older than schema 3, whose latency cells are empty).
std::vector<std::string> latency_cells(const ParticipantRow& participant) {
  if (!participant.latency_recorded) return {"", "", "", std::to_string(participant.dropped_frames), "not recorded"};
  return {csv_number(participant.latency.median_ms), csv_number(participant.latency.p95_ms),
          std::to_string(participant.latency.refreshes), std::to_string(participant.dropped_frames),
          participant.present_clock};
}

// The frame-interval columns: the refresh rate they are measured against, the intervals counted,
// their median, SD, p99 and max (ms), and the late ones (beyond 1.5 refresh periods), as a count
// and a share; empty numbers without intervals.
std::vector<std::string> frame_interval_cells(const FrameIntervalSummary& frames) {
  return {csv_number(frames.refresh_hz),
          std::to_string(frames.intervals),
          csv_number(frames.median_ms),
          csv_number(frames.sd_ms),
          csv_number(frames.p99_ms),
          csv_number(frames.max_ms),
          frames.intervals ? std::to_string(frames.late) : "",
          csv_number(frames.late_share)};
}

// The eye-tracker validation columns: attempts, passed, and over the passed ones the mean and worst
// accuracy and the mean precision (all empty when the study validated nothing).
std::vector<std::string> validation_cells(const ParticipantRow& participant) {
  const ValidationSummary& validation = participant.validation;
  if (validation.attempts == 0) return {"", "", "", "", ""};
  return {std::to_string(validation.attempts), std::to_string(validation.passed),
          csv_number(validation.mean_accuracy_deg), csv_number(validation.worst_accuracy_deg),
          csv_number(validation.mean_precision_deg)};
}

}  // namespace

std::string conditions_csv(const AnalysisResult& result) {
  std::string csv = csv_line({"study", "protocol", "scene", "variant", "method", "condition", "level", "n", "k",
                              "proportion", "ci_lower", "ci_upper", "p_value", "p_holm", "stars", "alternative",
                              "mean_rating", "sd_rating", "log10_p"});
  for (const ConditionRow& row : result.conditions) {
    csv += csv_line({result.study, std::string(result.rules().name), row.group.scene, row.group.variant, row.method,
                     row.condition, csv_number(row.level), std::to_string(row.n), std::to_string(row.k),
                     csv_number(row.proportion), csv_number(row.interval.lower), csv_number(row.interval.upper),
                     csv_number(row.p_value), csv_number(row.p_holm), shown_stars(result, row),
                     alternative_name(result.alternative), csv_number(row.mean_rating), csv_number(row.sd_rating),
                     csv_number(row.log10_p)});
  }
  return csv;
}

// adaptive_tracks.csv: one row a participant's adaptive track (staircase or QUEST+), with its
// threshold by the procedure's rule and its levels and answers (';'-separated, in trial order).
std::string adaptive_tracks_csv(const AnalysisResult& result) {
  std::string csv =
      csv_line({"participant",     "observer",    "excluded", "block",     "procedure", "kind",      "variant",
                "track",           "start_level", "trials",   "reversals", "stopped",   "threshold", "threshold_lower",
                "threshold_upper", "slope",       "lapse",    "note",      "levels",    "seen"});
  for (const ParticipantRow& participant : result.participants)
    for (const AdaptiveTrackResult& track : participant.tracks) {
      std::string levels, seen;
      for (size_t i = 0; i < track.levels.size(); ++i) {
        levels.append(i ? ";" : "").append(csv_number(track.levels[i]));
        seen.append(i ? ";" : "").append(track.seen[i] ? "1" : "0");
      }
      const bool staircase = track.kind == "staircase";
      csv += csv_line({participant.participant,
                       participant.observer,
                       participant.excluded ? "true" : "false",
                       track.block,
                       track.procedure,
                       track.kind,
                       track.variant,
                       std::to_string(track.track),
                       csv_number(track.start_level),
                       std::to_string(track.levels.size()),
                       staircase ? std::to_string(track.reversal_trials.size()) : "",
                       track.stopped ? "true" : "false",
                       csv_number(track.threshold),
                       csv_number(track.threshold_lower),
                       csv_number(track.threshold_upper),
                       csv_number(track.slope),
                       csv_number(track.lapse),
                       track.note,
                       levels,
                       seen});
    }
  return csv;
}

std::string participants_csv(const AnalysisResult& result) {
  std::string csv = csv_line({"participant",
                              "observer",
                              "excluded",
                              "session_ended",
                              "complete_trials",
                              "attention_checks",
                              "attention_errors",
                              "scene",
                              "variant",
                              "threshold",
                              "note",
                              "log_status",
                              "latency_median_ms",
                              "latency_p95_ms",
                              "latency_refreshes",
                              "dropped_frames",
                              "present_clock",
                              "practice_trials",
                              "validation_attempts",
                              "validations_passed",
                              "validation_accuracy_deg",
                              "validation_worst_accuracy_deg",
                              "validation_precision_deg",
                              "gaze_source",
                              "refresh_hz",
                              "frame_intervals",
                              "frame_interval_median_ms",
                              "frame_interval_sd_ms",
                              "frame_interval_p99_ms",
                              "frame_interval_max_ms",
                              "frame_intervals_late",
                              "frame_intervals_late_share"});
  for (const ParticipantRow& participant : result.participants) {
    const std::vector<std::string> common = {participant.participant,
                                             participant.observer,
                                             participant.excluded ? "true" : "false",
                                             participant.session_ended ? "true" : "false",
                                             std::to_string(participant.complete_trials),
                                             std::to_string(participant.attention_checks),
                                             std::to_string(participant.attention_errors)};
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
      cells.insert(cells.end(), {threshold.group.scene, threshold.group.variant, csv_number(threshold.level),
                                 threshold.note, log_status_name(participant.log_status)});
      cells.insert(cells.end(), tail.begin(), tail.end());
      csv += csv_line(cells);
    }
  }
  return csv;
}

// Ye et al. 2022's pilot grid: one row per map and cell.
std::string rating_grid_csv(const RatingGrid& grid, const std::string& study) {
  std::string csv =
      csv_line({"study", "scene", "level", "x_key", "x", "y_key", "y", "mean_score", "trials", "participants", "best"});
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
  std::string csv =
      csv_line({"study", "scene", "variant", "condition", "reference_method", "test_method", "n", "reference_votes",
                "share", "ci_lower", "ci_upper", "p_value", "alternative", "stars", "log10_p"});
  for (const PreferenceRow& row : result.preferences) {
    csv += csv_line({row.study, row.group.scene, row.group.variant, row.condition, row.reference_method,
                     row.test_method, std::to_string(row.n), std::to_string(row.reference_votes), csv_number(row.share),
                     csv_number(row.interval.lower), csv_number(row.interval.upper), csv_number(row.p_value), "greater",
                     row.stars, csv_number(row.log10_p)});
  }
  return csv;
}

// headline.csv: one row a (scene, variant) group, the number to publish with its interval, status
// and method, and the paper's rule beside it (docs/analysis.md). No value when not estimable.
std::string headline_csv(const AnalysisResult& result) {
  std::string csv = csv_line({"scene",
                              "variant",
                              "quantity",
                              "value",
                              "lower",
                              "upper",
                              "status",
                              "reason",
                              "method",
                              "aims_at",
                              "flags",
                              "participants",
                              "paper_rule",
                              "paper_value",
                              "paper_difference",
                              "paper_rule_is_headline",
                              "pooled_fit",
                              "pooled_fit_lower",
                              "pooled_fit_upper",
                              "notes"});
  for (const Headline& headline : result.headlines) {
    csv += csv_line({headline.group.scene,
                     headline.group.variant,
                     headline.quantity,
                     csv_number(headline_value(headline)),
                     csv_number(headline_lower(headline)),
                     csv_number(headline_upper(headline)),
                     headline_status_name(headline.status),
                     headline.reason,
                     headline.method,
                     headline.aims_at,
                     joined(headline.flags, "; "),
                     std::to_string(headline.participants),
                     headline.paper_rule,
                     csv_number(headline.paper_value),
                     headline.paper_difference,
                     headline.paper_rule_is_headline ? "true" : "false",
                     csv_number(headline.pooled_fit),
                     csv_number(headline.pooled_fit_lower),
                     csv_number(headline.pooled_fit_upper),
                     joined(headline.notes, "; ")});
  }
  return csv;
}
}  // namespace fovlab::analysis::report_detail
