#pragma once
// The fully expanded schedule of one participant's session: a pure function of (config, participant
// ID), computed before the first trial. Everything random here comes from Pcg32 streams derived
// from the session seed (core/prng.h), so a replay rebuilds the identical plan from the log header.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "study/config/study_config.h"
#include "study/stimulus/stimulus_spec.h"

namespace fovlab {

struct PlannedStimulus {
  StimulusSpec spec;
  bool is_reference = false;
  std::string variant;          // test stimuli: the variant name ("" when there are none)
  std::optional<double> level;  // test stimuli: the level value (none without [levels])
};

struct Trial {
  int index = 0;          // position in the session, from 0
  int block = 0;          // index into StudyPlan::blocks (session order)
  std::string condition;  // "level=32", "blur/level=7.5", "ramp_up", "attention_check"...
  std::string variant;
  std::optional<double> level;        // the test level of comparison trials
  bool attention_check = false;       // both intervals show the reference
  bool reference_first = true;        // comparison trials: the reference is the first interval
  bool ramp_toward_reference = true;  // ramp: quality increases along the sequence
  std::vector<int> sequence;          // stimulus ids in presentation order (slider: the level ladder)
  int reference = -1;                 // the block's reference stimulus id
  int slider_start = 0;               // slider: index into sequence where adjustment starts
  bool practice = false;              // a [practice] trial (never analysed)
  // An adaptive trial: its track (index into StudyPlan::tracks). The schedule leaves its level,
  // test stimulus and condition open (sequence empty); AdaptiveProgress::presented fills them in
  // from the answers before it (study/schedule/adaptive_progress.h).
  int track = -1;
};

struct PlannedBlock {
  std::string name;
  std::string scene;
  int first_trial = 0;
  int trial_count = 0;
  bool practice = false;  // the [practice] trials' block: first, named "practice"
};

// One track of an adaptive block: a staircase of a variant from one of its procedure's starts, or
// the variant's QUEST+.
struct AdaptiveTrack {
  int block = 0;      // index into StudyPlan::blocks
  int procedure = 0;  // index into StudyConfig::procedures
  ProcedureConfig::Kind kind = ProcedureConfig::Kind::staircase;
  std::string variant;
  StaircaseRule staircase;        // a staircase: start_index is this track's start on the grid
  QuestPlusRule quest;            // QUEST+ (quest_plus_rule: the grids for this variant's levels)
  std::vector<double> grid;       // level values, easiest first (adaptive_grid)
  std::vector<int> grid_stimuli;  // the test stimulus id of each grid level
  int max_trials() const { return kind == ProcedureConfig::Kind::staircase ? staircase.max_trials : quest.max_trials; }
};

struct StudyPlan {
  StudyConfig config;
  std::string participant;
  uint64_t session_seed = 0;
  std::vector<PlannedStimulus> stimuli;  // distinct stimuli; a stimulus id is an index here
  std::vector<PlannedBlock> blocks;      // in session order (the practice block first when there is one)
  std::vector<Trial> trials;             // in session order
  std::vector<AdaptiveTrack> tracks;     // the adaptive blocks' tracks (staircases, QUEST+)

  // Estimated session length: stimuli, black intervals, inter-trial and block rests, plus
  // `response_s` per answer (slider: half the ladder's steps, each one viewing and one answer),
  // and the eye-tracker validations that pass at the first attempt.
  double expected_duration_s(double response_s = 1.5) const;
};

// The participant ID names a folder: 1-64 of [A-Za-z0-9_-], not starting with '-'. Throws
// InputError otherwise. Every reader of a log holds its header's participant to this rule.
void check_participant_id(const std::string& participant);
// A participant a session may start or resume now: check_participant_id, and not a reserved name
// (is_reserved_participant_id). Logs of a reserved name made by an older fovlab stay readable.
void check_new_participant_id(const std::string& participant);
// "analysis" in any letter case: results/<study>/analysis is fovlab analyze's report folder (its
// temporaries beside it hold a '.', which IDs cannot).
bool is_reserved_participant_id(const std::string& participant);

uint64_t session_seed(uint64_t study_seed, const std::string& participant);

// A comparison condition's name: "level=32", "blur/level=7.5", the variant alone, or "test".
std::string condition_name(const std::string& variant, std::optional<double> level);

// Slider: where the ladder stands after `answer` ("up" toward the reference, "down" away; other
// answers and the ends of the ladder leave it where it is).
int next_ladder_index(const Trial& trial, const std::string& answer, int ladder_index);

StudyPlan make_study_plan(const StudyConfig& config, const std::string& participant);

// A balanced Latin square of n blocks (Williams design): n rows for an even n, 2n for an odd one;
// each row an order of 0..n-1, each block in each position equally often and, over the rows, each
// block right after every other one equally often. block_order = "latin_square" gives participant
// number k row (k - 1) mod rows.
std::vector<std::vector<int>> balanced_latin_square(int n);
// The number an ID ends with ("P007": 7), at most 9 digits; none without a trailing digit.
std::optional<int> participant_number(const std::string& participant);

// The specs of the plan's stimuli, in id order (for StimulusLibrary and its memory check).
std::vector<StimulusSpec> planned_specs(const StudyPlan& plan);

}  // namespace fovlab
