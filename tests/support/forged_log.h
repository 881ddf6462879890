#pragma once
// What a forger without the lab key does to a session log, for the tests that it is caught: edit
// lines, then renumber and re-chain every event with the public algorithm, so that the chain itself
// holds again (the MACs of a keyed log, which need the key, are kept as they were, or removed with
// the header's lab_key_id).
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "study/log/event_log.h"

namespace fovlab::testing {

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  size_t begin = 0;
  for (size_t end = text.find('\n'); end != std::string::npos; begin = end + 1, end = text.find('\n', begin))
    lines.push_back(text.substr(begin, end - begin));
  return lines;
}

// `lines` renumbered and re-chained; with `recount_seals` each seal also commits the trials
// completed before it (trial_end events, a session without resumes), as a forger who deleted or
// added a trial would make it.
inline std::string rechained(const std::vector<std::string>& lines, bool strip_keys = false,
                             bool recount_seals = false) {
  std::string text, chain;
  int64_t seq = 0;
  int trials_complete = 0;
  for (const std::string& line : lines) {
    nlohmann::json event = nlohmann::json::parse(line);
    event.erase("chain");
    const nlohmann::json old_mac = event.value("mac", nlohmann::json());
    event.erase("mac");
    if (strip_keys && event.contains("lab_key_id")) event["lab_key_id"] = nullptr;
    event["seq"] = seq++;
    if (event.value("event", "") == "trial_end") ++trials_complete;
    if (event.value("event", "") == "seal") {
      event["last_chain"] = chain;
      if (recount_seals) event["trials_complete"] = trials_complete;
    }
    chain = event_chain(chain, event);
    event["chain"] = chain;
    if (!strip_keys && !old_mac.is_null()) event["mac"] = old_mac;
    text += event.dump() + "\n";
  }
  return text;
}

// The first line holding `needle`, with `from` replaced by `to`; the text re-chained.
inline std::string forged(const std::string& original, const std::string& needle, const std::string& from,
                          const std::string& to) {
  std::vector<std::string> lines = lines_of(original);
  for (std::string& line : lines) {
    if (line.find(needle) == std::string::npos) continue;
    const size_t at = line.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    line.replace(at, from.size(), to);
    break;
  }
  return rechained(lines);
}

}  // namespace fovlab::testing
