#include "protocols/observer/simulated_observer.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <sstream>

#include "core/input_error.h"
#include "core/prng.h"

namespace fovlab {
namespace {

Pcg32 stream(uint64_t seed, int trial, int step) {
  return Pcg32(derive_seed(derive_seed(seed, static_cast<uint64_t>(trial)), static_cast<uint64_t>(step)));
}

double response_time(Pcg32& random, double mean_s) {
  const double floor_s = std::min(0.3, mean_s);
  return floor_s + random.exponential(std::max(1e-3, mean_s - floor_s));
}

}  // namespace

namespace {
// The logit of p_see: positive on the degraded side of the threshold.
double see_logit(const ObserverModel& model, double level) {
  const double z = model.slope * (level - model.threshold);
  return model.higher_is_better ? -z : z;
}
}  // namespace

double ObserverModel::p_see(std::optional<double> level) const {
  if (!level) return 0.0;
  const double z = slope * (*level - threshold);
  const double rising = 1.0 / (1.0 + std::exp(-z));
  return higher_is_better ? 1.0 - rising : rising;
}

double ObserverModel::visible_degradation(std::optional<double> level) const {
  if (!level) return 0.0;
  return fovlab::visible_degradation(see_logit(*this, *level));
}

double ObserverModel::p_detect(std::optional<double> level) const {
  return guess + (1.0 - guess - lapse) * p_see(level);
}

ObserverModel parse_observer_spec(const std::string& text, const StudyPlan& plan) {
  const std::string prefix = "simulated";
  if (text.rfind(prefix, 0) != 0 || (text.size() > prefix.size() && text[prefix.size()] != ':'))
    throw InputError("--observer: expected simulated[:threshold=T,slope=S,guess=G,lapse=L,rt=R,seed=N], got \"" + text +
                     "\"");
  ObserverModel model;
  const std::vector<double>& levels = plan.config.levels.values;
  if (!levels.empty()) {
    model.threshold = 0.5 * (levels.front() + levels.back());
    const double range = levels.back() - levels.front();
    model.slope = range > 0 ? 8.0 / range : 1.0;
  }
  model.higher_is_better = plan.config.levels.higher_is_better;
  model.seed = derive_seed(plan.session_seed, "observer");
  std::istringstream pairs(text.size() > prefix.size() ? text.substr(prefix.size() + 1) : "");
  std::string pair;
  while (std::getline(pairs, pair, ',')) {
    const size_t equals = pair.find('=');
    const std::string key = pair.substr(0, equals);
    const std::string value_text = equals == std::string::npos ? "" : pair.substr(equals + 1);
    if (key == "seed") {  // all 64 bits, as the log header records seeds
      char* seed_end = nullptr;
      errno = 0;
      const unsigned long long seed = std::strtoull(value_text.c_str(), &seed_end, 10);
      if (value_text.empty() || value_text[0] == '-' || *seed_end != '\0' || errno == ERANGE)
        throw InputError("--observer: seed=" + value_text + ": expected a whole number in [0, 2^64)");
      model.seed = seed;
      continue;
    }
    char* end = nullptr;
    const double value = std::strtod(value_text.c_str(), &end);
    if (value_text.empty() || *end != '\0' || !std::isfinite(value))
      throw InputError("--observer: " + key + ": expected key=number, got \"" + pair + "\"");
    if (key == "threshold") model.threshold = value;
    else if (key == "slope" && value > 0) model.slope = value;
    else if (key == "guess" && value >= 0 && value < 1) model.guess = value;
    else if (key == "lapse" && value >= 0 && value < 1) model.lapse = value;
    else if (key == "rt" && value > 0) model.mean_response_s = value;
    else
      throw InputError("--observer: " + key + "=" + value_text +
                       ": expected threshold=number, slope>0, guess and lapse in [0,1), rt>0 or seed=whole number");
  }
  if (model.guess + model.lapse >= 1.0) throw InputError("--observer: expected guess + lapse < 1");
  return model;
}

std::optional<double> SimulatedObserver::level_of(int stimulus) const {
  const PlannedStimulus& planned = plan_.stimuli.at(static_cast<size_t>(stimulus));
  return planned.is_reference ? std::nullopt : planned.level;
}

ObserverAnswer SimulatedObserver::answer_comparison(const Trial& trial) const {
  Pcg32 random = stream(model_.seed, trial.index, 0);
  const std::optional<double> level = trial.attention_check ? std::nullopt : trial.level;
  // A test without levels (e.g. IPR against GT) is seen as often as a test at the threshold would be
  // when the study has no levels to place it on: p_see(threshold) = 0.5 unless threshold is moved.
  const std::optional<double> effective = (!trial.attention_check && !level) ? std::optional<double>(0.0) : level;
  const bool detected = random.uniform() < model_.p_detect(effective);
  ObserverAnswer answer;
  const ProtocolConfig& protocol = plan_.config.protocol;
  switch (protocol.kind) {
    case ProtocolKind::two_afc:
      if (protocol.two_afc_question == TwoAfcQuestion::same) {
        answer.answer = detected ? answers::different : answers::same;
      } else {
        const bool choose_reference = detected || random.uniform() < 0.5;
        answer.answer = (choose_reference == trial.reference_first) ? answers::first : answers::second;
      }
      break;
    case ProtocolKind::pair:
      answer.answer = !detected ? answers::same : (trial.reference_first ? answers::first : answers::second);
      break;
    case ProtocolKind::rating:
      // Seen differences are "significant" (1) as often as they are plainly visible.
      // Through a std::string: GCC 12's Release build warns falsely (-Wrestrict) on assigning the view.
      answer.answer =
          std::string(!detected ? answers::rating_3
                                : (random.uniform() < model_.p_see(effective) ? answers::rating_1 : answers::rating_2));
      break;
    default:
      answer.answer = answers::same;
  }
  answer.response_time_s = response_time(random, model_.mean_response_s);
  return answer;
}

ObserverAnswer SimulatedObserver::answer_ramp_step(const Trial& trial, int step) const {
  const double before = model_.visible_degradation(level_of(trial.sequence.at(static_cast<size_t>(step - 1))));
  const double now = model_.visible_degradation(level_of(trial.sequence.at(static_cast<size_t>(step))));
  const double p_seen = step_seen_probability(before, now);
  Pcg32 random = stream(model_.seed, trial.index, step);
  const double u = random.uniform();
  const double p_true = (1.0 - model_.guess - model_.lapse) * p_seen;
  ObserverAnswer answer;
  if (u < p_true) {
    answer.answer = now < before ? answers::increased : answers::decreased;
  } else if (u < p_true + model_.guess) {
    answer.answer = random.uniform() < 0.5 ? answers::increased : answers::decreased;
  } else {
    answer.answer = answers::same;
  }
  answer.response_time_s = response_time(random, model_.mean_response_s);
  return answer;
}

ObserverAnswer SimulatedObserver::answer_slider(const Trial& trial, int action, int ladder_index) const {
  Pcg32 random = stream(model_.seed, trial.index, action);
  ObserverAnswer answer;
  answer.response_time_s = response_time(random, model_.mean_response_s);
  if (action == 0) {  // look at the reference once before adjusting
    answer.answer = answers::reference;
    return answer;
  }
  const bool detected =
      random.uniform() < model_.p_detect(level_of(trial.sequence.at(static_cast<size_t>(ladder_index))));
  const bool can_improve = ladder_index + 1 < static_cast<int>(trial.sequence.size());
  // The ladder runs from least to most like the reference: "up" is toward the reference.
  answer.answer = detected && can_improve ? answers::up : answers::save;
  return answer;
}

}  // namespace fovlab
