#include "study/schedule/study_plan.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <string>

#include "core/input_error.h"
#include "core/number_text.h"
#include "core/prng.h"

namespace fovlab {
std::string condition_name(const std::string& variant, std::optional<double> level) {
  std::string name = variant;
  // append, not a chain of +: GCC 12's -O2 warns falsely (-Wrestrict) on the temporaries.
  if (level) name.append(name.empty() ? "" : "/").append("level=").append(format_number(*level, 6));
  return name.empty() ? "test" : name;
}

namespace {

class PlanBuilder {
 public:
  PlanBuilder(const StudyConfig& config, StudyPlan& plan) : config_(config), plan_(plan) {}

  int add_stimulus(const std::string& scene, const MethodConfig& method, const VariantConfig* variant,
                   std::optional<double> level, bool is_reference) {
    PlannedStimulus stimulus;
    stimulus.is_reference = is_reference;
    stimulus.level = level;
    stimulus.variant = variant ? variant->name : "";
    StimulusSpec& spec = stimulus.spec;
    spec.scene = scene;
    spec.width_px = config_.display.width_px;
    spec.height_px = config_.display.height_px;
    const ParameterLayer none;
    ParameterLayer level_layer;
    if (level) level_layer[config_.levels.parameter] = *level;
    spec.parameters =
        parameters_with(method.method, {&method.parameters, variant ? &variant->parameters : &none, &level_layer});
    fill_display_parameters(spec, method, variant, level.has_value());
    spec.frame_count = config_.stimulus.frame_count();
    spec.frames_per_second = config_.stimulus.frames_per_second;
    spec.camera_start_s = config_.stimulus.camera_start_s;
    // Found by its key in an index, not by comparing it with every stimulus so far: a plan of
    // thousands of variants took minutes to make that way (each comparison wrote two canonical texts).
    for (size_t id = stimulus_ids_.size(); id < plan_.stimuli.size(); ++id)  // stimuli another builder added
      stimulus_ids_.emplace(stimulus_key(plan_.stimuli[id]), int(id));
    const auto [found, added] = stimulus_ids_.emplace(stimulus_key(stimulus), int(plan_.stimuli.size()));
    if (added) plan_.stimuli.push_back(std::move(stimulus));
    return found->second;
  }

  // FIPR's display parameters the config did not set come from [display]: the physical size of the
  // stimulus image and the viewing distance. A stimulus of W x H pixels on a display of
  // width_px x height_px covers W / width_px of its width (the window presenter shows a frame
  // pixel for pixel, or integer-scaled, centred; stimuli are rendered at the display's size, so
  // this is the whole display today).
  void fill_display_parameters(StimulusSpec& spec, const MethodConfig& method, const VariantConfig* variant,
                               bool has_level) const {
    const DisplayConfig& display = config_.display;
    const auto given = [&](const std::string& name) {
      return method.parameters.count(name) > 0 || (variant && variant->parameters.count(name) > 0) ||
             (has_level && config_.levels.parameter == name);
    };
    StimulusDisplay* stimulus_display = display_of(spec.parameters);
    if (!stimulus_display) return;
    if (!given("display_width_mm"))
      stimulus_display->display_width_mm = display.width_mm * spec.width_px / display.width_px;
    if (!given("display_height_mm"))
      stimulus_display->display_height_mm = display.height_mm * spec.height_px / display.height_px;
    if (!given("viewing_distance_mm")) stimulus_display->viewing_distance_mm = display.viewing_distance_mm;
  }

  std::vector<Trial> block_trials(int block_index, const BlockConfig& block, Pcg32& random) {
    if (block.procedure >= 0) return adaptive_block_trials(block_index, block, random);
    const StimulusConfig& stimulus = config_.stimulus;
    const ProtocolConfig& protocol = config_.protocol;
    const int reference = add_stimulus(block.scene, stimulus.reference, nullptr, std::nullopt, true);
    const std::vector<const VariantConfig*> variants = tested_variants(stimulus);
    std::vector<Trial> trials;
    const auto base_trial = [&](const VariantConfig* variant) {
      Trial trial;
      trial.block = block_index;
      trial.reference = reference;
      trial.variant = variant ? variant->name : "";
      return trial;
    };
    for (const VariantConfig* variant : variants) {
      std::vector<std::optional<double>> levels;
      for (double value : variant_levels(config_.levels, variant)) levels.emplace_back(value);
      if (levels.empty()) levels.emplace_back(std::nullopt);
      if (protocol.kind == ProtocolKind::ramp || protocol.kind == ProtocolKind::slider) {
        // The ladder from the level least like the reference to the one most like it.
        std::vector<int> ladder;
        for (const auto& level : levels)
          ladder.push_back(add_stimulus(block.scene, stimulus.test, variant, level, false));
        if (!config_.levels.higher_is_better) std::reverse(ladder.begin(), ladder.end());
        for (int repeat = 0; repeat < protocol.repeats; ++repeat) {
          if (protocol.kind == ProtocolKind::slider) {
            Trial trial = base_trial(variant);
            trial.condition =
                (trial.variant.empty() ? "" : trial.variant + "/") + std::string(protocol_name(ProtocolKind::slider));
            trial.sequence = ladder;
            const std::vector<double>& values = variant_levels(config_.levels, variant);
            const auto start = std::find(values.begin(), values.end(), protocol.slider.start_level) - values.begin();
            trial.slider_start = config_.levels.higher_is_better ? int(start) : int(ladder.size()) - 1 - int(start);
            trials.push_back(std::move(trial));
            continue;
          }
          for (bool toward : {true, false}) {
            Trial trial = base_trial(variant);
            trial.ramp_toward_reference = toward;
            trial.condition = (trial.variant.empty() ? "" : trial.variant + "/") + (toward ? "ramp_up" : "ramp_down");
            trial.sequence = ladder;
            trial.sequence.push_back(reference);
            if (!toward) std::reverse(trial.sequence.begin(), trial.sequence.end());
            trials.push_back(std::move(trial));
          }
        }
        continue;
      }
      for (const auto& level : levels) {
        const int test = add_stimulus(block.scene, stimulus.test, variant, level, false);
        for (int repeat = 0; repeat < protocol.repeats; ++repeat) {
          Trial trial = base_trial(variant);
          trial.level = level;
          trial.condition = condition_name(trial.variant, level);
          trial.reference_first = protocol.counterbalance ? repeat % 2 == 0 : random.below(2) == 0;
          trial.sequence =
              trial.reference_first ? std::vector<int>{reference, test} : std::vector<int>{test, reference};
          trials.push_back(std::move(trial));
        }
      }
    }
    add_attention_checks(block_index, reference, trials);
    if (protocol.randomise_trials) random.shuffle(trials);
    return trials;
  }

  // An adaptive block: per variant, one staircase per start or one QUEST+, each track planned to its
  // max_trials, their trials interleaved (round robin, then shuffled with the attention checks when
  // trials are randomised). Every grid level is a stimulus of the plan.
  std::vector<Trial> adaptive_block_trials(int block_index, const BlockConfig& block, Pcg32& random) {
    const StimulusConfig& stimulus = config_.stimulus;
    const ProcedureConfig& procedure = config_.procedures.at(static_cast<size_t>(block.procedure));
    const int reference = add_stimulus(block.scene, stimulus.reference, nullptr, std::nullopt, true);
    const std::vector<const VariantConfig*> variants = tested_variants(stimulus);
    std::vector<int> block_tracks;
    for (const VariantConfig* variant : variants) {
      AdaptiveTrack track;
      track.block = block_index;
      track.procedure = block.procedure;
      track.kind = procedure.kind;
      track.variant = variant ? variant->name : "";
      track.grid = adaptive_grid(config_.levels, variant);
      for (double level : track.grid)
        track.grid_stimuli.push_back(add_stimulus(block.scene, stimulus.test, variant, level, false));
      std::vector<int> starts = {0};
      if (procedure.kind == ProcedureConfig::Kind::quest_plus) {
        track.quest = quest_plus_rule(procedure, config_.protocol, config_.levels, track.grid);
      } else {
        track.staircase = procedure.staircase;
        if (!procedure.starts.empty()) starts.clear();
        for (double start : procedure.starts)
          starts.push_back(
              static_cast<int>(std::find(track.grid.begin(), track.grid.end(), start) - track.grid.begin()));
      }
      for (int start : starts) {
        track.staircase.start_index = start;
        block_tracks.push_back(static_cast<int>(plan_.tracks.size()));
        plan_.tracks.push_back(track);
      }
    }
    std::vector<Trial> trials;
    for (int round = 0; round < procedure.max_trials(); ++round)
      for (int track : block_tracks) {
        Trial trial;
        trial.block = block_index;
        trial.reference = reference;
        trial.track = track;
        trial.variant = plan_.tracks[static_cast<size_t>(track)].variant;
        trial.condition = (trial.variant.empty() ? "" : trial.variant + "/") + procedure.name;
        trials.push_back(std::move(trial));
      }
    add_attention_checks(block_index, reference, trials);
    if (config_.protocol.randomise_trials) random.shuffle(trials);
    // The reference's interval alternates along each track's own trials (or is drawn).
    std::vector<int> seen(plan_.tracks.size(), 0);
    for (Trial& trial : trials)
      if (trial.track >= 0)
        trial.reference_first =
            config_.protocol.counterbalance ? seen[static_cast<size_t>(trial.track)]++ % 2 == 0 : random.below(2) == 0;
    return trials;
  }

  // Attention checks: identical stimuli, `share` of all the block's trials.
  void add_attention_checks(int block_index, int reference, std::vector<Trial>& trials) {
    const double share = config_.attention.share;
    const int checks = share > 0 ? static_cast<int>(std::lround(share / (1.0 - share) * double(trials.size()))) : 0;
    for (int check = 0; check < checks; ++check) {
      Trial trial;
      trial.block = block_index;
      trial.reference = reference;
      trial.attention_check = true;
      trial.condition = "attention_check";
      trial.sequence = {reference, reference};
      trials.push_back(std::move(trial));
    }
  }

 private:
  // What makes two planned stimuli one: the spec (its canonical text), reference or test, level and
  // variant.
  static std::string stimulus_key(const PlannedStimulus& stimulus) {
    std::string key = stimulus.spec.canonical();
    key.append(1, '\0').append(stimulus.is_reference ? "reference" : "test").append(1, '\0');
    key.append(stimulus.level ? format_number(*stimulus.level, 17) : std::string("none")).append(1, '\0');
    return key.append(stimulus.variant);
  }

  const StudyConfig& config_;
  StudyPlan& plan_;
  std::map<std::string, int> stimulus_ids_;  // by stimulus_key: the index of plan_.stimuli
};

// A plan's size before it is made, as the planner's loops make it: its trials, and the stimuli
// their sequences list (a ramp's trial lists its whole ladder). A config of 16 MiB can ask for more
// than memory holds (10,000 variants x 1000 repeats x a long ladder); a log of more than
// kMaxPlannedTrials trials could not be read back anyway (every trial logs four events or more of
// at least 64 bytes each: more than 1 GiB, max_log_bytes), so such a config is refused before any
// trial is made: by validate and run, and by export, analyze and replay reading a log that carries one.
void check_plan_size(const StudyConfig& config) {
  constexpr uint64_t kMaxPlannedTrials = 4'000'000, kMaxPlannedSequenceEntries = 64'000'000;
  uint64_t trials = config.practice.trials > 0 ? uint64_t(config.practice.trials) : 0, entries = 0;
  const std::vector<const VariantConfig*> variants = tested_variants(config.stimulus);
  const double with_checks = 1.0 / (1.0 - config.attention.share);
  for (const BlockConfig& block : config.blocks) {
    uint64_t block_trials = 0, block_entries = 0;
    for (const VariantConfig* variant : variants) {
      const uint64_t levels = std::max<uint64_t>(1, variant_levels(config.levels, variant).size());
      const uint64_t repeats = uint64_t(config.protocol.repeats);
      if (block.procedure >= 0) {
        const ProcedureConfig& procedure = config.procedures.at(size_t(block.procedure));
        block_trials += uint64_t(std::max<size_t>(1, procedure.starts.size())) * uint64_t(procedure.max_trials());
        block_entries += uint64_t(std::max<size_t>(1, procedure.starts.size())) * levels;  // the track's grid
      } else if (config.protocol.kind == ProtocolKind::ramp) {
        block_trials += 2 * repeats;
        block_entries += 2 * repeats * (levels + 1);
      } else if (config.protocol.kind == ProtocolKind::slider) {
        block_trials += repeats;
        block_entries += repeats * levels;
      } else {
        block_trials += levels * repeats;
        block_entries += 2 * levels * repeats;
      }
    }
    trials += uint64_t(std::ceil(double(block_trials) * with_checks));
    entries += block_entries + 2 * uint64_t(std::ceil(double(block_trials) * with_checks));
    if (trials > kMaxPlannedTrials || entries > kMaxPlannedSequenceEntries) break;
  }
  if (trials > kMaxPlannedTrials)
    throw InputError(config.source_path + ": more than " + std::to_string(kMaxPlannedTrials) +
                     " trials planned a participant (a log of them could not be read back); expected fewer blocks, "
                     "variants, levels or [protocol] repeats");
  if (entries > kMaxPlannedSequenceEntries)
    throw InputError(
        config.source_path + ": more than " + std::to_string(kMaxPlannedSequenceEntries) +
        " presentations planned a participant; expected fewer blocks, variants, levels or [protocol] repeats");
}

}  // namespace

void check_participant_id(const std::string& participant) {
  const bool ok =
      !participant.empty() && participant.size() <= 64 && participant[0] != '-' &&
      std::all_of(participant.begin(), participant.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
      });
  if (!ok)
    throw InputError("--participant: expected 1-64 letters, digits, '_' or '-' (it names a folder), got \"" +
                     participant + "\"");
}

void check_new_participant_id(const std::string& participant) {
  check_participant_id(participant);
  if (is_reserved_participant_id(participant))
    throw InputError("--participant: \"" + participant +
                     "\" is reserved (results/<study>/analysis holds fovlab analyze's report); choose another ID");
}

bool is_reserved_participant_id(const std::string& participant) {
  std::string lower = participant;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower == "analysis";
}

int next_ladder_index(const Trial& trial, const std::string& answer, int ladder_index) {
  if (answer == "up" && ladder_index + 1 < static_cast<int>(trial.sequence.size())) return ladder_index + 1;
  if (answer == "down" && ladder_index > 0) return ladder_index - 1;
  return ladder_index;
}

uint64_t session_seed(uint64_t study_seed, const std::string& participant) {
  return derive_seed(study_seed, "participant:" + participant);
}

std::vector<StimulusSpec> planned_specs(const StudyPlan& plan) {
  std::vector<StimulusSpec> specs;
  for (const PlannedStimulus& stimulus : plan.stimuli) specs.push_back(stimulus.spec);
  return specs;
}

std::vector<std::vector<int>> balanced_latin_square(int n) {
  if (n < 1) return {};
  // Williams (1949): first row 0, 1, n-1, 2, n-2, ...; row r adds r to every entry (mod n). With
  // an even n each block follows every other block once; an odd n also needs the rows reversed.
  std::vector<int> first;
  for (int j = 0, low = 1, high = n - 1; j < n; ++j) first.push_back(j == 0 ? 0 : (j % 2 == 1 ? low++ : high--));
  std::vector<std::vector<int>> rows;
  for (int r = 0; r < n; ++r) {
    std::vector<int> row;
    for (int value : first) row.push_back((value + r) % n);
    rows.push_back(row);
  }
  if (n % 2 == 1)
    for (int r = 0; r < n; ++r) rows.emplace_back(rows[size_t(r)].rbegin(), rows[size_t(r)].rend());
  return rows;
}

std::optional<int> participant_number(const std::string& participant) {
  size_t digits = 0;
  while (digits < participant.size() && digits < 9 &&
         std::isdigit(static_cast<unsigned char>(participant[participant.size() - 1 - digits])))
    ++digits;
  if (digits == 0) return std::nullopt;
  return std::stoi(participant.substr(participant.size() - digits));
}

StudyPlan make_study_plan(const StudyConfig& config, const std::string& participant) {
  check_participant_id(participant);
  check_plan_size(config);
  StudyPlan plan;
  plan.config = config;
  plan.participant = participant;
  plan.session_seed = session_seed(config.seed, participant);

  std::vector<int> block_order(config.blocks.size());
  for (size_t i = 0; i < block_order.size(); ++i) block_order[i] = static_cast<int>(i);
  if (config.protocol.block_order == ProtocolConfig::BlockOrder::random) {
    Pcg32 random(derive_seed(plan.session_seed, "blocks"));
    random.shuffle(block_order);
  } else if (config.protocol.block_order == ProtocolConfig::BlockOrder::latin_square) {
    const std::vector<std::vector<int>> square = balanced_latin_square(static_cast<int>(block_order.size()));
    const std::optional<int> number = participant_number(participant);
    if (!number)
      throw InputError("participant \"" + participant +
                       "\": block_order = \"latin_square\" picks each participant's row "
                       "by the number the ID ends with (P001, P002, ...); expected an ID ending in a number");
    block_order = square[static_cast<size_t>((*number + int(square.size()) - 1) % int(square.size()))];
  }
  const auto add_block = [&plan](const std::string& name, const std::string& scene, std::vector<Trial> trials,
                                 bool practice) {
    PlannedBlock planned{name, scene, static_cast<int>(plan.trials.size()), static_cast<int>(trials.size()), practice};
    for (Trial& trial : trials) {
      trial.index = static_cast<int>(plan.trials.size());
      trial.practice = practice;
      plan.trials.push_back(std::move(trial));
    }
    plan.blocks.push_back(std::move(planned));
  };
  if (config.practice.trials > 0 && !config.blocks.empty()) {
    // The practice block: the study's conditions at the practice levels (the whole ladder for ramp
    // and slider), no attention checks, repeated and shuffled, then cut to the number asked for.
    StudyConfig practice = config;
    if (!config.practice.levels.empty()) {
      practice.levels.values = config.practice.levels;
      // A conditions file's variant keeps its own levels: those practised, else its easiest.
      for (VariantConfig& variant : practice.stimulus.variants) {
        if (variant.levels.empty()) continue;
        std::vector<double> kept;
        for (double level : variant.levels)
          if (std::find(config.practice.levels.begin(), config.practice.levels.end(), level) !=
              config.practice.levels.end())
            kept.push_back(level);
        if (kept.empty()) kept = {config.levels.higher_is_better ? variant.levels.front() : variant.levels.back()};
        variant.levels = kept;
      }
    }
    practice.attention.share = 0.0;
    // Enough repeats of the practice conditions for `trials`, no more.
    int per_repeat = 0;
    const std::vector<const VariantConfig*> variants = tested_variants(practice.stimulus);
    for (const VariantConfig* variant : variants)
      per_repeat += config.protocol.kind == ProtocolKind::ramp ? 2
                    : config.protocol.kind == ProtocolKind::slider
                        ? 1
                        : std::max<int>(1, static_cast<int>(variant_levels(practice.levels, variant).size()));
    practice.protocol.repeats = (config.practice.trials + per_repeat - 1) / per_repeat;
    practice.protocol.randomise_trials = true;
    BlockConfig block{"practice", config.practice.scene};
    if (block.scene.empty()) block.scene = config.blocks[static_cast<size_t>(block_order.front())].scene;
    Pcg32 random(derive_seed(plan.session_seed, "practice"));
    std::vector<Trial> trials = PlanBuilder(practice, plan).block_trials(0, block, random);
    trials.resize(static_cast<size_t>(config.practice.trials));
    add_block(block.name, block.scene, std::move(trials), true);
  }
  PlanBuilder builder(config, plan);
  for (int position = 0; position < static_cast<int>(block_order.size()); ++position) {
    const BlockConfig& block = config.blocks[static_cast<size_t>(block_order[static_cast<size_t>(position)])];
    Pcg32 random(derive_seed(plan.session_seed, "trials:" + block.name));
    add_block(block.name, block.scene, builder.block_trials(static_cast<int>(plan.blocks.size()), block, random),
              false);
  }
  return plan;
}

double StudyPlan::expected_duration_s(double response_s) const {
  const double stimulus_s = config.stimulus.frame_count() / config.stimulus.frames_per_second;
  const TimingConfig& timing = config.timing;
  double total = 0.0;
  for (const Trial& trial : trials) {
    // An adaptive trial's two intervals are chosen as it runs (every one counted: an upper bound
    // when a track stops early).
    double steps = trial.track >= 0 ? 2.0 : double(trial.sequence.size());
    double answers = 1.0;
    if (config.protocol.kind == ProtocolKind::ramp) answers = steps - 1.0;
    if (config.protocol.kind == ProtocolKind::slider) {
      steps = 1.0 + 0.5 * double(trial.sequence.size());  // the reference, then half the ladder
      answers = steps;
    }
    total += steps * stimulus_s + (steps - 1.0) * timing.black_interval_s + answers * response_s + timing.inter_trial_s;
  }
  // Rests come between the study's blocks (not after the practice block); an eye-tracker
  // validation (each target, plus a key press) at the start and after each rest.
  const auto study_blocks =
      std::count_if(blocks.begin(), blocks.end(), [](const PlannedBlock& block) { return !block.practice; });
  const double rests = study_blocks > 0 ? double(study_blocks - 1) : 0.0;
  total += rests * timing.rest_between_blocks_s;
  if (config.validation.enabled) {
    const double validation_s = config.validation.targets * config.validation.target_s + response_s;
    total += (1.0 + (config.validation.after_breaks && timing.rest_between_blocks_s > 0 ? rests : 0.0)) * validation_s;
  }
  return total;
}

}  // namespace fovlab
