#include "study/protocol/protocol_rules.h"

#include <algorithm>

namespace fovlab {
namespace {

using namespace answers;

// "first" or "second": whether the interval chosen held the test.
std::optional<bool> test_chosen(std::string_view answer, bool reference_first) {
  if (answer != first && answer != second) return std::nullopt;
  return (answer == first) != reference_first;
}

const ProtocolAnswer kFirst{first, {"1", "left", "pad_left"}};
const ProtocolAnswer kSecond{second, {"2", "right", "pad_right"}};
const ProtocolAnswer kSame{same, {"s", "space", "pad_a"}};

std::vector<ProtocolRules> make_rules() {
  std::vector<ProtocolRules> all;
  ProtocolRules same_2afc;
  same_2afc.kind = ProtocolKind::two_afc;
  same_2afc.question = TwoAfcQuestion::same;
  same_2afc.name = "2afc";
  same_2afc.question_name = "same";
  same_2afc.answers = {kSame, {different, {"d", "pad_b"}}};
  same_2afc.identical = same;
  same_2afc.default_question = "Was the quality the same in both sequences?";
  same_2afc.two_intervals = true;
  same_2afc.judges_against_reference = true;
  same_2afc.judged_words = "judged identical";
  same_2afc.threshold_definition = "Polychronakis et al. 2023, 4.4 and 5.1";
  all.push_back(same_2afc);

  ProtocolRules better_2afc = same_2afc;
  better_2afc.question = TwoAfcQuestion::better;
  better_2afc.question_name = "better";
  better_2afc.answers = {kFirst, kSecond};
  better_2afc.identical = "";
  better_2afc.default_question = "Which sequence had the better quality?";
  better_2afc.judged_words = "preferred";
  better_2afc.threshold_definition = "Ye et al. 2022, 5.2";
  all.push_back(better_2afc);

  ProtocolRules pair;
  pair.kind = ProtocolKind::pair;
  pair.name = "pair";
  pair.answers = {kFirst, kSecond, kSame};
  pair.identical = same;
  pair.default_question = "Which rendering was better, or were they the same?";
  pair.two_intervals = true;
  pair.judges_against_reference = true;
  pair.guess_rate_scale = 0.5;
  pair.judged_words = "judged as good or better";
  pair.threshold_definition = "Polychronakis et al. 2021, 4.7 (pooled)";
  all.push_back(pair);

  ProtocolRules ramp;
  ramp.kind = ProtocolKind::ramp;
  ramp.name = "ramp";
  ramp.answers = {{increased, {"up", "pad_up"}}, {decreased, {"down", "pad_down"}}, kSame};
  ramp.default_question = "Did the quality increase, decrease or stay the same?";
  all.push_back(ramp);

  ProtocolRules slider;
  slider.kind = ProtocolKind::slider;
  slider.name = "slider";
  slider.answers = {{up, {"up", "right", "pad_up"}},
                    {down, {"down", "left", "pad_down"}},
                    {reference, {"r", "pad_x"}},
                    {save, {"enter", "space", "pad_a"}}};
  slider.default_question = "Change the level until the quality matches the reference; save when it does.";
  all.push_back(slider);

  ProtocolRules rating;
  rating.kind = ProtocolKind::rating;
  rating.name = "rating";
  rating.answers = {{rating_1, {"1", "pad_b"}}, {rating_2, {"2", "pad_y"}}, {rating_3, {"3", "pad_a"}}};
  rating.identical = rating_3;
  rating.default_question = "Score the difference: 3 identical, 2 minimal difference, 1 significant difference.";
  rating.two_intervals = true;
  rating.judges_against_reference = true;
  rating.judged_words = "rated identical";
  rating.threshold_definition = "Ye et al. 2022, 4.4.2";
  all.push_back(rating);
  return all;
}

const std::vector<ProtocolRules>& rules() {
  static const std::vector<ProtocolRules> all = make_rules();
  return all;
}

}  // namespace

std::optional<bool> ProtocolRules::in_favour_of_test(std::string_view answer, bool reference_first) const {
  switch (kind) {
    case ProtocolKind::two_afc:
      if (question == TwoAfcQuestion::better) return test_chosen(answer, reference_first);
      if (answer == same) return true;
      if (answer == different) return false;
      return std::nullopt;
    case ProtocolKind::pair:
      return answer == same ? std::optional<bool>(true) : test_chosen(answer, reference_first);
    case ProtocolKind::rating:
      if (answer == rating_3) return true;
      if (answer == rating_1 || answer == rating_2) return false;
      return std::nullopt;
    case ProtocolKind::ramp:
    case ProtocolKind::slider:
      return std::nullopt;
  }
  return std::nullopt;
}

bool ProtocolRules::is_answer(std::string_view answer) const {
  return std::any_of(answers.begin(), answers.end(), [&](const ProtocolAnswer& a) { return a.name == answer; });
}

const ProtocolRules& protocol_rules(ProtocolKind kind, TwoAfcQuestion question) {
  for (const ProtocolRules& candidate : rules())
    if (candidate.kind == kind && (kind != ProtocolKind::two_afc || candidate.question == question)) return candidate;
  return rules().front();
}

std::optional<ProtocolKind> find_protocol(std::string_view name) {
  for (const ProtocolRules& candidate : rules())
    if (candidate.name == name) return candidate.kind;
  return std::nullopt;
}

std::optional<TwoAfcQuestion> find_two_afc_question(std::string_view name) {
  for (const ProtocolRules& candidate : rules())
    if (candidate.kind == ProtocolKind::two_afc && candidate.question_name == name) return candidate.question;
  return std::nullopt;
}

std::string known_protocols() {
  std::string text;
  for (const ProtocolRules& candidate : rules()) {
    const std::string name(candidate.name);
    if (text.find(name) == std::string::npos) text += (text.empty() ? "" : ", ") + name;
  }
  return text;
}

}  // namespace fovlab
