// The rules of each protocol (study/protocol/protocol_rules.h): names, answers, the identical
// answer, and which answers are in favour of the test, as docs/analysis.md defines them.
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "study/protocol/protocol_rules.h"

namespace fovlab {
namespace {

struct Case {
  ProtocolKind kind;
  TwoAfcQuestion question;
};
const Case kEveryProtocol[] = {
    {ProtocolKind::two_afc, TwoAfcQuestion::same}, {ProtocolKind::two_afc, TwoAfcQuestion::better},
    {ProtocolKind::pair, TwoAfcQuestion::same},    {ProtocolKind::ramp, TwoAfcQuestion::same},
    {ProtocolKind::slider, TwoAfcQuestion::same},  {ProtocolKind::rating, TwoAfcQuestion::same}};

TEST(ProtocolRules, NamesReadBackAndAnswersAreDistinct) {
  EXPECT_EQ(known_protocols(), "2afc, pair, ramp, slider, rating");
  for (const Case& c : kEveryProtocol) {
    const ProtocolRules& rules = protocol_rules(c.kind, c.question);
    SCOPED_TRACE(std::string(rules.name) + " " + std::string(rules.question_name));
    EXPECT_EQ(rules.kind, c.kind);
    EXPECT_EQ(find_protocol(rules.name), c.kind);
    std::set<std::string_view> names, keys;
    for (const ProtocolAnswer& answer : rules.answers) {
      EXPECT_TRUE(names.insert(answer.name).second) << answer.name;
      EXPECT_FALSE(answer.default_keys.empty()) << answer.name;
      for (std::string_view key : answer.default_keys)
        EXPECT_TRUE(keys.insert(key).second) << "key " << key << " twice";
    }
    if (!rules.identical.empty()) {
      EXPECT_TRUE(rules.is_answer(rules.identical));
    }
    EXPECT_FALSE(rules.default_question.empty());
    // Every answer of a judging protocol is in favour of the test or not; the others judge nothing.
    for (const ProtocolAnswer& answer : rules.answers)
      EXPECT_EQ(rules.in_favour_of_test(answer.name, true).has_value(), rules.judges_against_reference) << answer.name;
    EXPECT_FALSE(rules.in_favour_of_test("", true));  // a timeout says nothing
  }
  EXPECT_EQ(find_two_afc_question("better"), TwoAfcQuestion::better);
  EXPECT_FALSE(find_protocol("3afc"));
}

TEST(ProtocolRules, WhichAnswersAreInFavourOfTheTest) {
  const ProtocolRules& same = protocol_rules(ProtocolKind::two_afc, TwoAfcQuestion::same);
  EXPECT_EQ(same.in_favour_of_test(answers::same, true), true);
  EXPECT_EQ(same.in_favour_of_test(answers::different, false), false);
  EXPECT_EQ(same.identical, answers::same);
  const ProtocolRules& better = protocol_rules(ProtocolKind::two_afc, TwoAfcQuestion::better);
  EXPECT_EQ(better.in_favour_of_test(answers::first, /*reference_first=*/false), true);  // the test was first
  EXPECT_EQ(better.in_favour_of_test(answers::first, /*reference_first=*/true), false);
  EXPECT_EQ(better.in_favour_of_test(answers::second, true), true);
  EXPECT_TRUE(better.identical.empty());
  const ProtocolRules& pair = protocol_rules(ProtocolKind::pair);
  EXPECT_EQ(pair.in_favour_of_test(answers::same, true), true);
  EXPECT_EQ(pair.in_favour_of_test(answers::second, false), false);  // the reference was second
  EXPECT_EQ(pair.guess_rate_scale, 0.5);
  const ProtocolRules& rating = protocol_rules(ProtocolKind::rating);
  EXPECT_EQ(rating.in_favour_of_test(answers::rating_3, true), true);
  EXPECT_EQ(rating.in_favour_of_test(answers::rating_2, true), false);
  EXPECT_EQ(rating.in_favour_of_test(answers::rating_1, false), false);
  EXPECT_EQ(rating.identical, answers::rating_3);
  EXPECT_FALSE(protocol_rules(ProtocolKind::ramp).in_favour_of_test(answers::increased, true));
  EXPECT_TRUE(protocol_rules(ProtocolKind::slider).is_answer(answers::save));
  EXPECT_FALSE(protocol_rules(ProtocolKind::slider).two_intervals);
}

}  // namespace
}  // namespace fovlab
