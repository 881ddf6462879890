#pragma once
// Everything `fovlab analyze` computes for one study, in plain structs: the per-condition table,
// the participants, the thresholds per protocol, the psychometric fits, and what was left out and
// why. Produced by analyse_study (study_analysis.h); written as thresholds.json, conditions.csv,
// participants.csv, SVG plots and report.html by analysis/report/.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "analysis/fitting/psychometric_fit.h"
#include "analysis/statistics/binomial.h"
#include "analysis/statistics/frame_intervals.h"
#include "analysis/statistics/percentile.h"
#include "study/protocol/protocol_rules.h"
#include "study/log/log_integrity.h"

namespace fovlab::analysis {

using fovlab::LogStatus;

// A group of conditions that share a reference and a level axis: one scene (block scene, or "all"
// pooled over scenes) and one variant (e.g. "blur", or "" when the study has none).
struct GroupKey {
  std::string scene;
  std::string variant;
  bool operator<(const GroupKey& other) const {
    return scene != other.scene ? scene < other.scene : variant < other.variant;
  }
  bool operator==(const GroupKey& other) const { return scene == other.scene && variant == other.variant; }
  // "scene" or "scene/variant", as tables and messages name the group.
  std::string label() const { return variant.empty() ? scene : scene + "/" + variant; }
};

// One row of conditions.csv: the comparison trials of one condition over every included
// participant. k counts the answers in favour of the test stimulus (docs/analysis.md): judged
// identical (2afc "same", pair "same" or the test chosen, rating "3") or chosen as better (2afc
// "better").
struct ConditionRow {
  GroupKey group;
  std::string condition;  // as logged, e.g. "level=7.5"
  std::string method;     // of the test stimuli ("ipr", "fipr", ...; several: joined by "+")
  std::optional<double> level;
  uint64_t n = 0;
  uint64_t k = 0;
  double proportion = 0.0;            // k / n
  double p_value = 0.0;               // exact binomial test of k/n against 1/2, --alternative (0 below 1e-300)
  double log10_p = 0.0;               // its log10, also where p_value underflows (binomial.h)
  double p_holm = 0.0;                // Holm-adjusted across the levels of the group
  std::string stars;                  // of p_holm, the p the threshold uses
  ProportionInterval interval;        // Clopper-Pearson, 95 %
  std::optional<double> mean_rating;  // rating only: the mean score 1-3, and its SD
  std::optional<double> sd_rating;
};

// A participant's eye-tracker validations (the log's tracker_validation events): the attempts that
// passed and failed, and over those that passed the mean and worst accuracy and the mean precision
// (docs/gaze.md). `attempts` 0: the study validated nothing.
struct ValidationSummary {
  int attempts = 0;
  int passed = 0;
  std::optional<double> mean_accuracy_deg, worst_accuracy_deg, mean_precision_deg;
};

// One participant's threshold for one group (pair, ramp, slider), with how it was reached.
struct ParticipantThreshold {
  GroupKey group;
  std::optional<double> level;  // none: the definition found no level (see note)
  std::string note;             // e.g. "every step answered correctly: censored at 30"
};

// One adaptive track of a participant (docs/analysis.md): its levels and answers trial by trial,
// and its threshold by the procedure's own rule: a staircase's mean level of its last
// `reversals_averaged` reversals; QUEST+'s posterior mean with its 95 % credible interval.
struct AdaptiveTrackResult {
  int track = 0;  // in the participant's schedule (the log's trial_start "track")
  std::string block, procedure, variant;
  std::string kind;                   // "staircase" or "quest_plus"
  std::optional<double> start_level;  // a staircase's start
  std::vector<double> levels;         // each complete trial's level, in order
  std::vector<bool> seen;             // ... and whether its answer saw the difference
  std::vector<int> reversal_trials;   // a staircase: positions in `levels` of the trials that turned it
  bool stopped = false;               // a stopping rule was met
  int reversals_averaged = 0;         // a staircase's
  std::optional<double> threshold;    // none: a staircase with fewer reversals than it averages (see note)
  std::optional<double> threshold_lower, threshold_upper;  // QUEST+: the 95 % credible interval
  std::optional<double> slope, lapse;                      // QUEST+: posterior means
  std::string note;
};

// A headset session's eyes, from its log header's `headset` (docs/log-schema.md): what the report
// shows beside the frame timing and gaze figures, which in a headset hold for both eyes at once
// (each frame submits both eyes for one predicted display time; one gaze sample places both eyes'
// pixels).
struct HeadsetSummary {
  std::string runtime;  // the OpenXR runtime's name and version
  int eye_width_px = 0;
  int eye_height_px = 0;
  std::string view_model;     // "head-locked" or "head-tracked"
  std::string gaze_fixation;  // "rendered-depth" or "fixation-distance"
  std::optional<double> fixation_distance_mm;
  // Each eye's field of view [left, right, up, down] in degrees, left eye first (none: not logged).
  std::array<std::optional<std::array<double, 4>>, 2> fov_deg;
  // Refreshes of the complete trials' stimuli handed to the compositor after their predicted
  // display time (the stimulus events' late_frames, schema 12); nullopt: the log measured none (a
  // runtime without XR_KHR_convert_timespec_time, or schema 11).
  std::optional<int64_t> late_frames;
  // The gaze of the complete trials' refreshes (the scan's, session_scan.h): how many refreshes,
  // and how many the log marks invalid in each eye (index 0 left, 1 right), off that eye's image or
  // for another reason (no sample, not tracked). One combined gaze places both eyes' pixels and the
  // right eye's is made from the left's, so an invalid left gaze is invalid in the right eye too.
  // right_eye_marked: the log marks the right eye's (schema 13); before, its counts are unknown.
  int64_t gaze_refreshes = 0;
  std::array<int64_t, 2> gaze_off_image = {0, 0};
  std::array<int64_t, 2> gaze_invalid_other = {0, 0};
  bool right_eye_marked = false;
};

// `refreshes` as a share of the headset session's gaze refreshes, in [0, 1]; nullopt when it had
// none (not measured, not 0).
inline std::optional<double> gaze_refresh_share(const HeadsetSummary& headset, int64_t refreshes) {
  if (headset.gaze_refreshes <= 0) return std::nullopt;
  return static_cast<double>(refreshes) / static_cast<double>(headset.gaze_refreshes);
}

struct ParticipantRow {
  std::string participant;
  std::string log_path;
  std::string observer = "human";  // "human" or "simulated"
  int complete_trials = 0;
  int attention_checks = 0;
  int attention_errors = 0;
  bool excluded = false;  // by attention checks (session log says "excluded")
  bool session_ended = false;
  LogStatus log_status = LogStatus::sealed;  // unsealed: interrupted; broken: only with --include-broken
  std::string log_note;                      // why, when not sealed
  // Gaze-to-present latency (nearest-rank median and 95th percentile over every stimulus refresh
  // of the complete trials) and dropped frames; latency_recorded false for logs older than schema 3.
  bool latency_recorded = false;
  LatencySummary latency;
  int64_t dropped_frames = 0;
  // The intervals between presented refreshes of the complete trials' stimuli (every schema;
  // docs/analysis.md, "Frame intervals").
  FrameIntervalSummary frame_intervals;
  // The gaze source the session's runs used (the log header's gaze_source, schema 7; in an earlier
  // log, the kind its `gaze` spec names): "tracker", "trace", "synthetic", "mouse", or several
  // joined by "+" when a resumed run used another ("tracker+mouse"); "" when the log names none
  // (participants.csv: "not recorded").
  std::string gaze_source;
  std::string present_clock;
  std::optional<HeadsetSummary> headset;  // a headset session's: none for a window's or headless one
  ValidationSummary validation;
  int practice_trials = 0;  // complete practice trials (never analysed)
  std::vector<ParticipantThreshold> thresholds;
  std::vector<AdaptiveTrackResult> tracks;  // adaptive blocks: each track's levels, answers and threshold
};

// A study-level threshold for one group, with its definition (and seed section).
struct GroupThreshold {
  GroupKey group;
  std::string definition;       // one sentence, as in docs/analysis.md
  std::optional<double> level;  // none: no level satisfies the definition (see note)
  std::string note;
  // The data cannot support a threshold whatever the answers (too few trials for any level to be
  // distinguished, or a test that cannot distinguish): `level` is none and the note says why.
  bool unsupported = false;
  // Pair, ramp, slider: across participants with a threshold.
  std::optional<double> mean;
  std::optional<double> sd;          // sample SD (n - 1); none with fewer than two
  std::optional<double> mean_lower;  // 95 % Student-t interval of the mean (n - 1 degrees of freedom),
  std::optional<double> mean_upper;  // none with fewer than two
  int participants_with_threshold = 0;
  int participants_without_threshold = 0;
};

struct GroupFit {
  GroupKey group;
  std::vector<LevelCounts> data;        // k: differences reported (n - k of the condition rows)
  std::vector<PsychometricFit> fits;    // one per shape that could be fitted
  std::vector<std::string> not_fitted;  // "weibull: levels <= 0", ...
};

// Ye et al. 2022's pilot (4.3.1, 4.4.1): a rating study whose variants set two numeric parameters of the
// test method on a full grid (rating_grid.h). One cell is one (x, y) pair.
struct GridCell {
  double x = 0.0;
  double y = 0.0;
  // The mean over participants of each participant's mean score (1-3) in the cell; none: no trial.
  std::optional<double> mean_score;
  uint64_t trials = 0;   // answered trials counted
  int participants = 0;  // participants with at least one of them
};

// The grid of one block (or of every block pooled: scene "all"), over every level or at one level.
struct GridMap {
  std::string scene;
  std::optional<double> level;  // none: every level pooled
  std::vector<GridCell> cells;  // row-major: row r is y_values[r], column c is x_values[c]
  std::vector<size_t> best;     // the cells with the highest mean; more than one: a tie
};

struct RatingGrid {
  std::string x_key;  // the two parameter keys the variants set, in alphabetical order
  std::string y_key;
  std::vector<double> x_values;  // ascending
  std::vector<double> y_values;  // ascending
  // Per block (by name, as the conditions), then "all" when there are several; each block's map over
  // every level first, then one per level (ascending).
  std::vector<GridMap> maps;
};

// Ye et al. 2022, Table 2: one condition of a 2afc "better" study as the votes for the reference
// stimulus, tested one-sided (alternative greater: the reference preferred) against 1/2 whatever
// --alternative says (preference_table.h).
struct PreferenceRow {
  std::string study;
  GroupKey group;
  std::string condition;
  std::string reference_method;  // config names, e.g. "rmfr"
  std::string test_method;       // e.g. "hyperbolic"; several: joined by "+"
  uint64_t n = 0;                // answered trials
  uint64_t reference_votes = 0;  // the reference chosen as better
  double share = 0.0;            // reference_votes / n
  double p_value = 1.0;          // exact binomial, H0 p = 1/2, alternative greater (0 below 1e-300)
  double log10_p = 0.0;          // its log10, also where p_value underflows (binomial.h)
  std::string stars;             // "***", "**", "*" or "n.s."
  ProportionInterval interval;   // 95 % Clopper-Pearson interval of the share
};

// Whether a headline's value can be published as it stands (docs/analysis.md, "The headline").
enum class HeadlineStatus {
  estimated,      // value and interval are the method's estimate
  not_estimable,  // no value: the data cannot give one (threshold outside the levels, unbounded or
                  // zero-width interval, no convergence, too few participants); `reason` says which
  biased,         // a value whose method is known to miss what it aims at; `reason` gives the measured bias
};
inline const char* headline_status_name(HeadlineStatus status) {
  switch (status) {
    case HeadlineStatus::estimated:
      return "estimated";
    case HeadlineStatus::not_estimable:
      return "not estimable";
    case HeadlineStatus::biased:
      return "biased";
  }
  return "estimated";
}

// The one number a (scene, variant) group hands back (analysis/study/headline.h): its method
// follows from the study's design and is named; its status says whether it can be published as
// it stands. The paper's own rule (GroupThreshold) is kept beside it, labelled, with one line on
// why it differs when it does.
struct Headline {
  GroupKey group;
  std::string quantity;  // "threshold" (in the level parameter's units) or "preference share"
  std::string
      method;  // the estimator and its interval, in one phrase ("logistic fit, 95 % profile-likelihood interval")
  std::string aims_at;  // what the estimator aims at ("the level where p_see = 1/2", "p_report = 0.707", ...)
  HeadlineStatus status = HeadlineStatus::estimated;
  std::string reason;                  // why not estimable or biased; "" when estimated
  std::optional<double> value;         // none when not estimable
  std::optional<double> lower, upper;  // its 95 % interval; none where the method gives none (see reason)
  std::vector<std::string> flags;      // worth a look but no failure: "lapse at its bound (0)", "slope at its bound"
  std::vector<std::string> notes;      // the fit's notes and anything else a reader should see
  int participants = 0;                // participants whose data the value rests on
  // The paper's rule, kept beside the headline (its full definition is the GroupThreshold's).
  std::string paper_rule;  // e.g. "Polychronakis et al. 2021, 4.7"; "" when the design has none
  std::optional<double> paper_value;
  std::string paper_difference;  // one line on why the paper's rule gives another value; "" when it does not
  bool paper_rule_is_headline =
      false;  // the config chose the paper's rule as the headline ([analysis] headline = "paper")
  // Adaptive designs: the pooled psychometric fit of every adaptive trial of the group, beside the headline.
  std::optional<double> pooled_fit, pooled_fit_lower, pooled_fit_upper;
};

struct LeftOut {
  std::string what;  // a log path, or "participant P003", or a condition
  std::string reason;
};

// One version of the study's config among the logs read (StudyConfig::content_hash: what the
// config says, comments and formatting aside). Only one version is analysed; the others are named
// here, never pooled (fovlab run keeps them in results/<study>@vN: study/log/study_versions.h).
struct ConfigVersion {
  std::string content_hash;          // the version ("" when its config_toml could not be read: then its config_hash)
  std::string config_hash;           // of its first log's header (the config file's bytes)
  int sessions = 0;                  // readable logs of it (after copies, observers and broken logs were left out)
  std::vector<std::string> folders;  // the study folders its logs are in, in path order
  bool analysed = false;
};

// "version 1a2b3c4d5e6f7081: 5 session(s) in results/x, analysed" (or "..., not analysed: another
// version of the config, analyse it on its own"): one line per version in stdout and the report.
inline std::string describe_config_version(const ConfigVersion& version) {
  std::string folders;
  for (const std::string& folder : version.folders) folders += (folders.empty() ? "" : ", ") + folder;
  return "version " + (version.content_hash.empty() ? "config_hash " + version.config_hash : version.content_hash) +
         ": " + std::to_string(version.sessions) + " session(s) in " + folders +
         (version.analysed ? ", analysed" : ", not analysed (another version of the config: analyse it on its own)");
}

struct AnalysisResult {
  std::string study;
  ProtocolKind protocol = ProtocolKind::two_afc;
  TwoAfcQuestion question = TwoAfcQuestion::same;  // 2afc only
  const ProtocolRules& rules() const { return protocol_rules(protocol, question); }
  std::string level_parameter;  // e.g. "foveal_deg"; "" without levels
  bool higher_is_better = true;
  std::vector<double> levels;
  Alternative alternative = Alternative::two_sided;
  double alpha = 0.05;
  double rating_cutoff = 2.0;       // rating studies: the lowest acceptable mean score
  double guess_rate = 0.0;          // the fits' fixed guess rate
  std::string guess_rate_source;    // "2afc forced choice", "attention checks (12 of 240)", "--guess-rate"
  std::vector<std::string> inputs;  // the log paths read
  std::string observers = "human";  // who answered: "human", "simulated", "human and simulated" (pooled on request)
  std::vector<ConditionRow> conditions;
  std::vector<ParticipantRow> participants;
  std::vector<GroupThreshold> thresholds;
  std::vector<GroupFit> fits;
  std::optional<RatingGrid> rating_grid;       // rating studies whose variants form a 2-parameter grid
  std::vector<PreferenceRow> preferences;      // 2afc "better" studies: one row a condition row
  std::vector<Headline> headlines;             // one per (scene, variant) group, in group order
  FrameIntervalSummary frame_intervals;        // every included (not excluded) participant's, pooled
  std::vector<ConfigVersion> config_versions;  // every version found, the analysed one first
  std::vector<LeftOut> left_out;
};

}  // namespace fovlab::analysis
