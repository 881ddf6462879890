#pragma once
// The rules of each protocol, in one place: its name in configs and logs, the answers it collects
// (the words the log records), the answer that means "identical" (an attention check's correct
// answer), which answers say the test looked like the reference, and how its threshold is defined.
// The runner, the simulated observer, replay and the analysis all ask these rules; no other code
// spells a protocol's or an answer's name.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fovlab {

enum class ProtocolKind { two_afc, pair, ramp, slider, rating };
enum class TwoAfcQuestion { better, same };  // "which was better?" or "was the quality the same?"

// The answers any protocol collects, as the log and the config's [protocol.keys] write them.
namespace answers {
inline constexpr std::string_view same = "same";
inline constexpr std::string_view different = "different";
inline constexpr std::string_view first = "first";
inline constexpr std::string_view second = "second";
inline constexpr std::string_view increased = "increased";
inline constexpr std::string_view decreased = "decreased";
inline constexpr std::string_view up = "up";
inline constexpr std::string_view down = "down";
inline constexpr std::string_view reference = "reference";  // slider: show the reference again
inline constexpr std::string_view save = "save";            // slider: keep the current level
inline constexpr std::string_view rating_1 = "1";
inline constexpr std::string_view rating_2 = "2";
inline constexpr std::string_view rating_3 = "3";  // rating: identical to the reference
// A ramp step's right answer: the ramp's direction (toward the reference: the quality increased).
inline std::string_view ramp_correct_answer(bool toward_reference) { return toward_reference ? increased : decreased; }
}  // namespace answers

struct ProtocolAnswer {
  std::string_view name;
  std::vector<std::string_view> default_keys;  // key names of display/presenter.h
};

struct ProtocolRules {
  ProtocolKind kind = ProtocolKind::two_afc;
  TwoAfcQuestion question = TwoAfcQuestion::same;  // 2afc only
  std::string_view name;                           // "2afc", "pair", "ramp", "slider", "rating"
  std::string_view question_name;                  // 2afc: "same" or "better"; else ""
  std::vector<ProtocolAnswer> answers;             // in order; [protocol.keys] must map exactly these
  std::string_view identical;                      // the answer meaning "identical"; "" when none
  std::string_view default_question;               // the question screen's text unless the config sets one
  bool two_intervals = false;  // a trial shows the reference and the test, in an order to counterbalance
  // The answers judge the test against the reference (2afc, pair, rating): an exact binomial test of
  // the share judged like the reference, per condition (docs/analysis.md).
  bool judges_against_reference = false;
  // pair: either interval may be picked, so the false-alarm rate counts half (Polychronakis et al. 2021, 4.7).
  double guess_rate_scale = 1.0;
  std::string_view judged_words;          // "judged identical", ...
  std::string_view threshold_definition;  // where the threshold's definition comes from

  // Whether `answer` is in favour of the test stimulus (judged identical, as good or better,
  // preferred; docs/analysis.md); nullopt when it says nothing (a timeout, or a protocol that does
  // not judge against the reference).
  std::optional<bool> in_favour_of_test(std::string_view answer, bool reference_first) const;
  bool is_answer(std::string_view answer) const;
};

const ProtocolRules& protocol_rules(ProtocolKind kind, TwoAfcQuestion question = TwoAfcQuestion::same);
// The protocol a config's `kind` names; nullopt when none.
std::optional<ProtocolKind> find_protocol(std::string_view name);
std::optional<TwoAfcQuestion> find_two_afc_question(std::string_view name);
// "2afc, pair, ramp, slider, rating": for messages.
std::string known_protocols();

}  // namespace fovlab
