#pragma once
// A study's logs as the analysis needs them: per participant, the complete trials with their
// scene, condition, level and answers. Logs are read through the runner's log reader
// (study/log) and never modified. A log that cannot be used (unreadable, another study or
// config, a schema this build does not read, a duplicate participant) is left out with its reason;
// the rest is still analysed.
#include <optional>
#include <string>
#include <vector>

#include "analysis/study/analysis_result.h"
#include "study/config/study_config.h"
#include "study/log/log_integrity.h"

namespace fovlab::analysis {

using fovlab::LabKey;

struct StudyTrial {
  int index = 0;
  std::string scene;      // of the trial's stimuli
  std::string condition;  // as logged ("level=7.5", "blur/ramp_up", ...)
  std::string variant;
  std::string method;           // of the test stimulus ("" for attention checks)
  std::optional<double> level;  // comparison trials with levels
  bool attention_check = false;
  bool reference_first = true;                         // comparison trials
  bool ramp_toward_reference = true;                   // ramp
  std::vector<std::optional<double>> sequence_levels;  // ramp: level of each stimulus shown (none: the reference)
  std::vector<std::string> answers;                    // in order ("" after a timeout)
  std::vector<int> answer_steps;                       // the `step` of each answer
  std::optional<double> saved_level;                   // slider
  std::optional<int> track;                            // an adaptive trial: its track in the participant's schedule
};

struct ParticipantData {
  std::string participant;
  std::string log_path;
  std::string observer = "human";  // "human", or "simulated" (the header's observer model)
  bool excluded = false;
  bool session_ended = false;
  int attention_checks = 0;
  int attention_errors = 0;
  std::vector<StudyTrial> trials;            // complete trials, in session order
  LogStatus log_status = LogStatus::sealed;  // unsealed: interrupted; broken: only with include_broken
  std::string log_note;                      // the verdict in words, when not sealed
  // Gaze-to-present latency over the complete trials' stimulus refreshes, from the log's
  // gaze_age_s (schema 3); a schema 1-2 log has none (latency_recorded false: "not recorded").
  bool latency_recorded = false;
  LatencySummary latency;
  int64_t dropped_frames = 0;              // refresh periods missed in the complete trials (every schema)
  FrameIntervalSummary frame_intervals;    // between the complete trials' presented refreshes (every schema)
  std::string present_clock;               // "virtual", "after_queue_present", "present_wait"; several: joined by "+"
  std::optional<HeadsetSummary> headset;   // the header's `headset` (a headset session)
  ValidationSummary validation;            // the eye-tracker validations (every attempt in the log)
  std::string gaze_source;                 // gaze_kinds as text (ParticipantRow::gaze_source)
  std::vector<GazeSourceKind> gaze_kinds;  // the gaze sources its runs used, in order (log_events.h session_gaze_kinds)
  int practice_trials = 0;                 // complete practice trials: counted here, never in `trials`
};

struct StudyData {
  std::string study;
  std::string config_hash;
  ProtocolKind protocol = ProtocolKind::two_afc;
  TwoAfcQuestion question = TwoAfcQuestion::same;  // 2afc only
  const ProtocolRules& rules() const { return protocol_rules(protocol, question); }
  std::string level_parameter;
  std::vector<double> levels;  // ascending
  bool higher_is_better = true;
  // The stimuli of the config the logs carry: the reference's and the test's method, and the
  // variants' overrides of the test's parameters (the pilot grid of Ye et al. 2022: rating_grid.h).
  RenderMethod reference_method = RenderMethod::ground_truth;
  RenderMethod test_method = RenderMethod::ground_truth;
  std::vector<VariantConfig> variants;  // in config order; empty: one unnamed variant
  StudyConfig config;                   // the whole config the logs carry (adaptive blocks: each schedule is rebuilt)
  // The levels the variant named `variant` is tested at (study_config.h variant_levels): its own
  // (a conditions file's), else `levels`.
  const std::vector<double>& levels_of(const std::string& variant) const;
  std::vector<std::string> inputs;            // every log path given (sorted)
  std::vector<ParticipantData> participants;  // in log-path order
  std::vector<LeftOut> left_out;
  // Every config version among the logs (the analysed one first, then by sessions): the logs of
  // the others are counted there, not listed in left_out one by one.
  std::vector<ConfigVersion> config_versions;
  // Who answered in the participants analysed: "human", "simulated", or "human and simulated" when
  // pooled on request (--observers all).
  std::string observers = "human";
  // The gaze sources of the sessions analysed, when worth a word on the study line: "" (nothing to
  // say), or e.g. "mouse gaze: rehearsals" when every session of a gaze-contingent study had the
  // mouse as gaze, "mouse gaze pooled with the other sources by --gaze-sources all".
  std::string gaze_note;
};

// The fields of `data` a config gives (study, protocol, levels, methods, variants, the config
// itself): what load_study takes from a log's config_toml, and `fovlab simulate` from its config.
void describe_study_config(const StudyConfig& config, StudyData& data);

// Which sessions an analysis takes by who answered. Simulated sessions never mix with real
// participants unless asked: by default a study with both is refused, naming the counts.
enum class ObserverFilter { unmixed, human, simulated, all };
std::optional<ObserverFilter> parse_observer_filter(const std::string& text);  // "human", "simulated", "all"

// Which sessions an analysis takes by their gaze source (docs/analysis.md, "Gaze sources"). By
// default (`all` false, `kinds` empty) a gaze-contingent study whose sessions had gaze from the mouse
// (rehearsals) and from another source leaves the mouse sessions out, each named; `all` pools every
// source; `kinds` keeps only the sessions whose every run had a source of those kinds.
struct GazeSourceFilter {
  bool all = false;
  std::vector<GazeSourceKind> kinds;
};
// "all", or kinds separated by commas ("tracker", "tracker,trace"); InputError "--gaze-sources: ..."
// naming what was expected.
GazeSourceFilter parse_gaze_source_filter(const std::string& text);

struct LoadOptions {
  const LabKey* lab_key = nullptr;  // verify keyed seals
  bool include_broken = false;      // analyse logs whose chain or seal is broken (else left out)
  ObserverFilter observers = ObserverFilter::unmixed;
  GazeSourceFilter gaze_sources;
};

// `paths`: log files and/or folders (every events.jsonl under them), all of one study: logs of
// several studies are refused (InputError naming each study and its count of logs), as is a study
// whose sessions mix human and simulated observers without `observers` saying which to take.
// The config version (StudyConfig::content_hash) most readable logs carry is analysed (ties: the
// one whose first log comes first in sorted path order), every version found is in
// config_versions; logs of another version, sessions of the observers not taken, and
// broken logs (unless include_broken), and sessions of the gaze sources not taken (gaze_sources) are
// left out; unsealed logs are analysed and listed. Throws
// InputError when no log at all can be read (naming the first reason).
StudyData load_study(const std::vector<std::string>& paths, const LoadOptions& options = {});

}  // namespace fovlab::analysis
