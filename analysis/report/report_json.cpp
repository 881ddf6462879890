#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "analysis/report/report_formats.h"

namespace fovlab::analysis::report_detail {
namespace {

using json = nlohmann::ordered_json;  // keys in the documented order

// A JSON number, or null for none and for non-finite values (JSON has no NaN).
json json_number(double value) { return std::isfinite(value) ? json(value) : json(nullptr); }
json json_number(const std::optional<double>& value) { return value ? json_number(*value) : json(nullptr); }

json adaptive_tracks_json(const ParticipantRow& participant) {
  json tracks = json::array();
  for (const AdaptiveTrackResult& track : participant.tracks) {
    json levels = json::array();
    for (double level : track.levels) levels.push_back(json_number(level));
    json entry = {{"track", track.track}, {"block", track.block},     {"procedure", track.procedure},
                  {"kind", track.kind},   {"variant", track.variant}, {"levels", levels},
                  {"seen", track.seen},   {"stopped", track.stopped}, {"threshold", json_number(track.threshold)},
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

// One headline in thresholds.json's `headlines`: value and interval null when not estimable.
json headline_json(const Headline& headline) {
  json pooled = nullptr;
  if (headline.pooled_fit)
    pooled = {{"value", json_number(headline.pooled_fit)},
              {"interval",
               {{"lower", json_number(headline.pooled_fit_lower)}, {"upper", json_number(headline.pooled_fit_upper)}}}};
  return {{"scene", headline.group.scene},
          {"variant", headline.group.variant},
          {"quantity", headline.quantity},
          {"value", json_number(headline_value(headline))},
          {"interval",
           {{"lower", json_number(headline_lower(headline))}, {"upper", json_number(headline_upper(headline))}}},
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
          {"late_beyond_ms",
           frames.refresh_hz ? json_number(kLateRefreshPeriods * 1e3 / *frames.refresh_hz) : json(nullptr)},
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

// A headset session's eyes (only for one): as its log header gave them, angles in degrees.
json headset_json(const HeadsetSummary& headset) {
  // Each eye's gaze quality: the shares of refreshes whose gaze was invalid (no sample, not tracked)
  // and whose pixel fell off that eye's image. A log before schema 13 marks the left eye's only; the
  // right eye's invalid share is then the left's (one gaze, both eyes alike) and its off-image share
  // null (not logged).
  json eyes = json::array();
  for (size_t eye = 0; eye < 2; ++eye) {
    const std::optional<std::array<double, 4>>& fov = headset.fov_deg[eye];
    const bool marked = eye == 0 || headset.right_eye_marked;
    const size_t counted = marked ? eye : 0;
    eyes.push_back(
        {{"fov_deg", fov ? json(*fov) : json(nullptr)},
         {"gaze_invalid_share", json_number(gaze_refresh_share(headset, headset.gaze_invalid_other[counted]))},
         {"gaze_off_image_share",
          marked ? json_number(gaze_refresh_share(headset, headset.gaze_off_image[eye])) : json(nullptr)}});
  }
  return {{"runtime", headset.runtime},
          {"eye_width_px", headset.eye_width_px},
          {"eye_height_px", headset.eye_height_px},
          {"view_model", headset.view_model},
          {"gaze_fixation", headset.gaze_fixation},
          {"fixation_distance_mm", json_number(headset.fixation_distance_mm)},
          {"eyes", eyes},
          {"late_frames", headset.late_frames ? json(*headset.late_frames) : json(nullptr)},  // null: not measured
          {"gaze_refreshes", headset.gaze_refreshes}};
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
    root["thresholds"].push_back(
        {{"scene", threshold.group.scene},
         {"variant", threshold.group.variant},
         {"definition", threshold.definition},
         {"level", json_number(threshold.level)},
         {"supported", !threshold.unsupported},
         {"note", threshold.note},
         {"mean", json_number(threshold.mean)},
         {"sd", json_number(threshold.sd)},
         {"mean_interval",
          {{"lower", json_number(threshold.mean_lower)}, {"upper", json_number(threshold.mean_upper)}}},
         {"participants_with_threshold", threshold.participants_with_threshold},
         {"participants_without_threshold", threshold.participants_without_threshold}});
  }

  root["fits"] = json::array();
  root["not_fitted"] = json::array();
  for (const GroupFit& group : result.fits) {
    json data = json::array();
    for (const LevelCounts& counts : group.data) {
      data.push_back(
          {{"level", json_number(counts.level)},
           {"n", counts.n},
           {"k_difference", counts.k},
           {"proportion", counts.n > 0 ? json_number(static_cast<double>(counts.k) / static_cast<double>(counts.n))
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
      maps.push_back(
          {{"scene", map.scene},
           {"level", json_number(map.level)},
           {"best", best},
           {"best_mean_score", map.best.empty() ? json(nullptr) : json_number(map.cells[map.best[0]].mean_score)},
           {"tie", map.best.size() > 1},
           {"cells", cells}});
    }
    root["rating_grid"] = {{"definition",
                            "Ye et al. 2022, 4.4.1: per cell, each participant's mean score (1-3) over the "
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
    if (participant.headset) root["participants"].back()["headset"] = headset_json(*participant.headset);
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

}  // namespace

std::string thresholds_json_text(const AnalysisResult& result) {
  return thresholds_json(result).dump(2, ' ', false, json::error_handler_t::replace) + "\n";
}

}  // namespace fovlab::analysis::report_detail
