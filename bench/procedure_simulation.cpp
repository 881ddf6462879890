#include "bench/procedure_simulation.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <map>
#include <tuple>
#include <thread>

#include "analysis/fitting/psychometric_fit.h"
#include "analysis/study/study_analysis.h"
#include "analysis/study/study_data.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "protocols/observer/simulated_observer.h"
#include "study/schedule/adaptive_progress.h"
#include "study/schedule/study_plan.h"

namespace fovlab::bench {
namespace {

// One procedure (per block and variant) of one simulated participant.
struct Outcome {
  std::optional<double> estimate;
  int trials = 0;
};

struct Key {
  int block_order = 0;  // the block's index in the config
  std::string procedure, variant;
  int max_trials = 0;
  bool operator<(const Key& other) const {
    return std::tie(block_order, procedure, variant, max_trials) <
           std::tie(other.block_order, other.procedure, other.variant, other.max_trials);
  }
};

struct ParticipantRun {
  std::map<Key, Outcome> outcomes;
  ObserverModel model;
  analysis::ParticipantData data;  // the trials as a log would give them to the analysis
};

// A presented trial as the analysis reads it from a log (analysis/study/study_data.h), answered by
// the observer as a session asks: one answer (comparisons), one a ramp step, or slider actions up
// to "save" (protocols/session/session_run.cpp run_slider).
analysis::StudyTrial answered_trial(const StudyPlan& plan, const SimulatedObserver& observer, const Trial& trial) {
  analysis::StudyTrial logged;
  logged.index = trial.index;
  logged.scene = plan.blocks.at(static_cast<size_t>(trial.block)).name;
  logged.condition = trial.condition;
  logged.variant = trial.variant;
  logged.level = trial.level;
  logged.attention_check = trial.attention_check;
  logged.reference_first = trial.reference_first;
  logged.ramp_toward_reference = trial.ramp_toward_reference;
  if (trial.track >= 0) logged.track = trial.track;
  const auto level_of = [&](int id) { return plan.stimuli.at(static_cast<size_t>(id)).level; };
  if (!trial.attention_check) {
    for (int id : trial.sequence) logged.sequence_levels.push_back(level_of(id));
    logged.method = std::string(describe(plan.config.stimulus.test.method).name);
  }
  switch (plan.config.protocol.kind) {
    case ProtocolKind::ramp:
      for (int step = 1; step < static_cast<int>(trial.sequence.size()); ++step) {
        logged.answers.push_back(observer.answer_ramp_step(trial, step).answer);
        logged.answer_steps.push_back(step);
      }
      break;
    case ProtocolKind::slider: {
      int ladder_index = trial.slider_start;
      for (int action = 0; action < 100000; ++action) {
        const std::string answer = observer.answer_slider(trial, action, ladder_index).answer;
        logged.answers.push_back(answer);
        logged.answer_steps.push_back(action + 1);
        if (answer == answers::save) {
          logged.saved_level = level_of(trial.sequence.at(static_cast<size_t>(ladder_index)));
          break;
        }
        ladder_index = next_ladder_index(trial, answer, ladder_index);
      }
      break;
    }
    default:
      logged.answers.push_back(observer.answer_comparison(trial).answer);
      logged.answer_steps.push_back(static_cast<int>(trial.sequence.size()));
  }
  return logged;
}

// The level where the observer's p_report (p_detect) equals `target`, by bisection over the levels'
// range (p_detect is monotone in the level); NaN when the range does not reach it.
double level_where_p_detect_is(const ObserverModel& model, double target, double low, double high) {
  const auto f = [&](double x) { return model.p_detect(x) - target; };
  double a = low, b = high, fa = f(a), fb = f(b);
  if (fa * fb > 0) return std::nan("");
  for (int i = 0; i < 200; ++i) {
    const double m = 0.5 * (a + b), fm = f(m);
    if ((fm <= 0) == (fa <= 0)) a = m, fa = fm;
    else b = m;
  }
  return 0.5 * (a + b);
}

// One participant's session, answered by the observer, every adaptive procedure's max_trials set
// to `max_trials` (0: as configured).
ParticipantRun run_participant(const StudyConfig& base, const std::string& participant,
                               const std::string& observer_spec, int max_trials) {
  StudyConfig config = base;
  if (max_trials > 0)
    for (ProcedureConfig& procedure : config.procedures) {
      procedure.staircase.max_trials = max_trials;
      procedure.quest.max_trials = max_trials;
    }
  const StudyPlan plan = make_study_plan(config, participant);
  ParticipantRun run;
  run.model = parse_observer_spec(observer_spec, plan);
  const SimulatedObserver observer(run.model, plan);
  AdaptiveProgress progress(plan);
  // Each planned block's index in the config (summaries are in config order), looked up once.
  std::vector<int> config_block(plan.blocks.size(), -1);
  for (size_t b = 0; b < plan.blocks.size(); ++b)
    for (size_t i = 0; i < config.blocks.size(); ++i)
      if (config.blocks[i].name == plan.blocks[b].name) config_block[b] = static_cast<int>(i);
  std::map<Key, std::map<double, analysis::LevelCounts>> counts;  // constant stimuli, by level
  std::vector<int> track_trials(plan.tracks.size(), 0);
  run.data.participant = participant;
  run.data.observer = "simulated";
  const bool compares = config.protocol.rules().judges_against_reference;
  for (const Trial& planned : plan.trials) {
    if (planned.practice) continue;
    const std::optional<Trial> trial = progress.presented(planned);
    if (!trial) continue;
    run.data.trials.push_back(answered_trial(plan, observer, *trial));
    const std::string& answer = run.data.trials.back().answers.back();
    progress.record(planned, answer);
    run.data.attention_checks += trial->attention_check ? 1 : 0;
    if (!compares || trial->attention_check || !trial->level) continue;
    if (planned.track >= 0) {
      ++track_trials[static_cast<size_t>(planned.track)];
      continue;
    }
    analysis::LevelCounts& level =
        counts[Key{config_block[static_cast<size_t>(trial->block)], "constant", trial->variant, 0}][*trial->level];
    level.level = *trial->level;
    ++level.n;
    level.k += difference_seen(config.protocol, answer, trial->reference_first) ? 1 : 0;
  }
  for (size_t i = 0; i < plan.tracks.size(); ++i) {
    const AdaptiveTrack& track = plan.tracks[i];
    const int index = static_cast<int>(i);
    Outcome outcome;
    outcome.trials = track_trials[i];
    if (const QuestPlus* quest = progress.quest(index))
      outcome.estimate = quest->estimate(progress.quest_state(index).posterior).threshold_mean;
    else outcome.estimate = staircase_threshold(track.staircase, progress.staircase(index), track.grid);
    const ProcedureConfig& procedure = config.procedures.at(static_cast<size_t>(track.procedure));
    // Interleaved staircases of one variant are reported apart, by their start.
    std::string name = procedure.name;
    if (procedure.starts.size() > 1)
      name.append(" from ").append(format_number(track.grid.at(size_t(track.staircase.start_index)), 6));
    run.outcomes[Key{config_block[static_cast<size_t>(track.block)], name, track.variant, track.max_trials()}] =
        outcome;
  }
  for (const auto& [key, by_level] : counts) {
    std::vector<analysis::LevelCounts> data;
    Outcome outcome;
    for (const auto& [level, count] : by_level) {
      data.push_back(count);
      outcome.trials += static_cast<int>(count.n);
    }
    if (data.size() >= 2) {
      analysis::FitOptions options;
      options.rising = !config.levels.higher_is_better;
      options.guess = run.model.guess;
      options.bootstrap_samples = 0;
      const analysis::PsychometricFit fit = analysis::fit_psychometric(data, options);
      if (fit.converged && std::isfinite(fit.model.parameters.threshold))
        outcome.estimate = fit.model.parameters.threshold;
    }
    run.outcomes[key] = outcome;
  }
  return run;
}

// What the headline's method aims at for observers of `model` (procedure_simulation.h); NaN: nothing.
double headline_aim(const StudyConfig& config, const ObserverModel& model, const analysis::Headline& headline,
                    double low, double high) {
  if (headline.quantity != "threshold") return std::nan("");
  const auto block = std::find_if(config.blocks.begin(), config.blocks.end(),
                                  [&](const BlockConfig& b) { return b.name == headline.group.scene; });
  const BlockConfig& first = block == config.blocks.end() ? config.blocks.front() : *block;
  if (first.procedure >= 0) {
    const ProcedureConfig& procedure = config.procedures.at(static_cast<size_t>(first.procedure));
    return procedure.kind == ProcedureConfig::Kind::staircase
               ? level_where_p_detect_is(model, staircase_target_probability(procedure.staircase), low, high)
               : model.threshold;
  }
  if (config.protocol.kind == ProtocolKind::rating) {  // the walk on expected mean scores: 3 - p_detect (1 + p_see)
    std::vector<double> best_first = config.levels.values;
    if (config.levels.higher_is_better) std::reverse(best_first.begin(), best_first.end());
    double aim = std::nan("");
    for (double level : best_first) {
      if (3.0 - model.p_detect(level) * (1.0 + model.p_see(level)) < analysis::AnalysisOptions{}.rating_cutoff) break;
      aim = level;
    }
    return aim;
  }
  if (config.protocol.kind == ProtocolKind::slider) {  // from the start, a step up while a difference is seen
    const StudyPlan plan = make_study_plan(config, "S000001");
    for (const Trial& trial : plan.trials) {
      if (trial.practice || trial.sequence.empty() || trial.variant != headline.group.variant) continue;
      double expected = 0.0, reach = 1.0;
      for (size_t i = size_t(trial.slider_start); i < trial.sequence.size(); ++i) {
        const std::optional<double> level = plan.stimuli.at(static_cast<size_t>(trial.sequence[i])).level;
        const double save = i + 1 < trial.sequence.size() ? 1.0 - model.p_detect(level) : 1.0;
        expected += level.value_or(std::nan("")) * reach * save;
        reach *= 1.0 - save;
      }
      return expected;
    }
    return std::nan("");
  }
  return model.threshold;  // the fits (2afc, pair) and the ramp's step model
}

}  // namespace

SimulationResult simulate_study(const StudyConfig& config, const SimulationOptions& options) {
  if (options.participants < 1 || options.participants > 1000000)
    throw InputError("--participants: expected 1 to 1000000 simulated participants, got " +
                     std::to_string(options.participants));
  if (options.observer.find("seed=") != std::string::npos)
    throw InputError("--observer: expected no seed= (each simulated participant's answers are seeded by its ID)");
  for (int trials : options.max_trials)
    if (trials < 1 || trials > 10000)
      throw InputError("--max-trials: expected values from 1 to 10000, got " + std::to_string(trials));
  const auto start = std::chrono::steady_clock::now();
  std::vector<int> sweeps = options.max_trials;
  if (sweeps.empty()) sweeps = {0};
  // Participant p of sweep s: run index p * sweeps + s. Constant stimuli are kept from the first sweep.
  const size_t runs = size_t(options.participants) * sweeps.size();
  if (options.threads < 0 || options.threads > 256)
    throw InputError("--threads: expected 0 (every core) to 256, got " + std::to_string(options.threads));
  std::vector<ParticipantRun> results(runs);
  std::vector<std::exception_ptr> errors(runs);
  const int threads = options.threads > 0 ? options.threads : std::max(1, int(std::thread::hardware_concurrency()));
  std::atomic<size_t> next{0};
  const auto work = [&] {
    for (size_t run = next++; run < runs; run = next++) {
      char id[24];
      std::snprintf(id, sizeof id, "S%06zu", run / sweeps.size() + 1);
      try {
        results[run] = run_participant(config, id, options.observer, sweeps[run % sweeps.size()]);
      } catch (...) {
        errors[run] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);  // the first participant's error, as it was thrown

  SimulationResult result;
  result.threads = threads;
  const ObserverModel& model = results.front().model;
  result.observer_threshold = model.threshold;
  result.observer_slope = model.slope;
  result.observer_guess = model.guess;
  result.observer_lapse = model.lapse;
  // The tested range (NaN without levels: a 2afc "better" study may have none).
  const std::vector<double>& levels = config.levels.values;
  const double low = levels.empty() ? std::nan("") : *std::min_element(levels.begin(), levels.end());
  const double high = levels.empty() ? std::nan("") : *std::max_element(levels.begin(), levels.end());
  std::map<Key, std::vector<Outcome>> by_key;
  for (size_t run = 0; run < runs; ++run)
    for (const auto& [key, outcome] : results[run].outcomes)
      if (key.procedure != "constant" || run % sweeps.size() == 0) by_key[key].push_back(outcome);
  for (const auto& [key, outcomes] : by_key) {
    ProcedureSummary summary;
    summary.block = config.blocks.at(static_cast<size_t>(key.block_order)).name;
    summary.procedure = key.procedure;
    summary.variant = key.variant;
    summary.max_trials = key.max_trials;
    const std::string base_name = key.procedure.substr(0, key.procedure.find(" from "));
    const auto procedure = std::find_if(config.procedures.begin(), config.procedures.end(),
                                        [&](const ProcedureConfig& p) { return p.name == base_name; });
    summary.kind = procedure == config.procedures.end()                   ? "constant"
                   : procedure->kind == ProcedureConfig::Kind::quest_plus ? "quest_plus"
                                                                          : "staircase";
    summary.truth = model.threshold;
    if (summary.kind == "staircase") {
      summary.truth = level_where_p_detect_is(model, staircase_target_probability(procedure->staircase), low, high);
    }
    summary.participants = static_cast<int>(outcomes.size());
    double sum = 0.0, trials = 0.0;
    std::vector<double> estimates;
    for (const Outcome& outcome : outcomes) {
      trials += outcome.trials;
      if (outcome.estimate && std::isfinite(*outcome.estimate)) estimates.push_back(*outcome.estimate);
    }
    summary.estimates = static_cast<int>(estimates.size());
    summary.mean_trials = trials / double(outcomes.size());
    for (double value : estimates) sum += value;
    if (!estimates.empty()) {
      summary.mean_estimate = sum / double(estimates.size());
      summary.bias = summary.mean_estimate - summary.truth;
      double squares = 0.0, errors_squared = 0.0;
      for (double value : estimates) {
        squares += (value - summary.mean_estimate) * (value - summary.mean_estimate);
        errors_squared += (value - summary.truth) * (value - summary.truth);
      }
      summary.sd = estimates.size() > 1 ? std::sqrt(squares / double(estimates.size() - 1)) : std::nan("");
      summary.rmse = std::sqrt(errors_squared / double(estimates.size()));
    }
    result.summaries.push_back(std::move(summary));
  }
  // The first sweep's participants, analysed as their logs would be.
  analysis::StudyData data;
  analysis::describe_study_config(config, data);
  data.observers = "simulated";
  for (size_t run = 0; run < runs; run += sweeps.size()) data.participants.push_back(std::move(results[run].data));
  for (const analysis::Headline& headline : analysis::analyse_study(data, analysis::AnalysisOptions{}).headlines)
    result.headlines.push_back({headline, headline_aim(config, model, headline, low, high)});
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace fovlab::bench
