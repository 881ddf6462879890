// Tests of study/log/event_log.h (the chained JSONL session log) and session_record.h (a session
// as its log tells it).
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/content_hash.h"
#include "core/digest.h"
#include "core/input_error.h"
#include "study/log/event_log.h"
#include "study/log/session_record.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

using nlohmann::json;

using fovlab::testing::TempDir;

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

std::vector<std::string> lines_of(const std::string& bytes) {
  std::vector<std::string> lines;
  std::istringstream in(bytes);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string join_lines(const std::vector<std::string>& lines) {
  std::string bytes;
  for (const std::string& line : lines) bytes += line + "\n";
  return bytes;
}

std::string write_three(const TempDir& dir) {
  const std::string path = dir.file("events.jsonl");
  EventLogWriter writer(path, "", 0);
  writer.append(
      {{"event", "session_header"}, {"schema_version", log_schema_version}, {"study", "s"}, {"participant", "p"}});
  writer.append({{"event", "trial_start"}, {"trial", 0}, {"t", 1.5}});
  writer.append({{"event", "trial_end"}, {"trial", 0}, {"t", 2.5}});
  return path;
}

// --- the event log ------------------------------------------------------------------------------------

TEST(ProtocolsLog, WriterAndReaderAgree) {
  TempDir dir;
  const std::string path = write_three(dir);
  const std::string bytes = read_bytes(path);
  ASSERT_EQ(lines_of(bytes).size(), 3u);
  EXPECT_EQ(bytes.back(), '\n');

  const EventLogFile log = read_event_log(path);
  EXPECT_EQ(log.path, path);
  ASSERT_EQ(log.events.size(), 3u);
  EXPECT_EQ(log.line_numbers, (std::vector<int>{1, 2, 3}));
  EXPECT_FALSE(log.torn_tail.has_value());
  EXPECT_EQ(log.intact_bytes, bytes.size());
  EXPECT_EQ(log.first_chain_error_line, 0);
  EXPECT_EQ(log.events[1]["event"], "trial_start");
  EXPECT_EQ(log.events[1]["trial"], 0);
  EXPECT_EQ(log.events[1]["t"], 1.5);

  // seq counts from 0; chain_i = SHA-256(chain_{i-1} followed by event_i without "chain"), chain_{-1} = "".
  std::string previous;
  for (size_t i = 0; i < log.events.size(); ++i) {
    const json& event = log.events[i];
    EXPECT_EQ(event.at("seq").get<int64_t>(), static_cast<int64_t>(i));
    json without = event;
    without.erase("chain");
    const std::string expected = sha256_hex(previous, without.dump());
    EXPECT_EQ(event_chain(previous, without), expected);
    EXPECT_EQ(event.at("chain").get<std::string>(), expected) << "event " << i;
    EXPECT_EQ(expected.size(), 64u);
    previous = expected;
  }
  EXPECT_EQ(log.last_chain, previous);
  // Each line is the event's compact JSON.
  EXPECT_EQ(lines_of(bytes)[2], log.events[2].dump());
}

TEST(ProtocolsLog, OneLinePerEventWhateverTheText) {
  TempDir dir;
  const std::string path = dir.file("events.jsonl");
  const std::string text = "two\nlines, a \"quote\", a tab\t and \u00e9";
  {
    EventLogWriter writer(path, "", 0);
    writer.append({{"event", "note"}, {"text", text}});
    writer.append({{"event", "note"}, {"nested", {{"a", {1, 2, 3}}}}});
    EXPECT_GE(writer.seconds_writing(), 0.0);
    EXPECT_EQ(writer.path(), path);
  }
  EXPECT_EQ(lines_of(read_bytes(path)).size(), 2u);
  const EventLogFile log = read_event_log(path);
  ASSERT_EQ(log.events.size(), 2u);
  EXPECT_EQ(log.events[0]["text"], text);
  EXPECT_EQ(log.events[1]["nested"]["a"][2], 3);
  EXPECT_EQ(log.first_chain_error_line, 0);
}

TEST(ProtocolsLog, WriterReplacesSeqAndChainGivenByTheCaller) {
  TempDir dir;
  const std::string path = dir.file("events.jsonl");
  {
    EventLogWriter writer(path, "", 0);
    writer.append({{"event", "a"}, {"seq", 99}, {"chain", "forged"}});
    writer.append({{"event", "b"}});
  }
  const EventLogFile log = read_event_log(path);
  ASSERT_EQ(log.events.size(), 2u);
  EXPECT_EQ(log.events[0]["seq"], 0);
  EXPECT_NE(log.events[0]["chain"], "forged");
  EXPECT_EQ(log.first_chain_error_line, 0);
}

TEST(ProtocolsLog, EmptyLog) {
  const EventLogFile log = parse_event_log("", "empty.jsonl");
  EXPECT_TRUE(log.events.empty());
  EXPECT_FALSE(log.torn_tail.has_value());
  EXPECT_EQ(log.intact_bytes, 0u);
  EXPECT_EQ(log.first_chain_error_line, 0);
  EXPECT_EQ(log.last_chain, "");
}

TEST(ProtocolsLog, AModifiedLineBreaksTheChainThere) {
  TempDir dir;
  const std::string path = write_three(dir);
  std::vector<std::string> lines = lines_of(read_bytes(path));
  // Change a value, keep "seq" and "chain": the chain no longer matches.
  json edited = json::parse(lines[1]);
  edited["t"] = 1.75;
  lines[1] = edited.dump();
  write_bytes(path, join_lines(lines));
  const EventLogFile log = read_event_log(path);
  EXPECT_EQ(log.first_chain_error_line, 2);
  EXPECT_EQ(log.events.size(), 3u);  // still parsed: the chain is a check, not a parse error
  EXPECT_EQ(log.events[1]["t"], 1.75);

  // The same edit on the last line.
  TempDir other_dir;
  std::vector<std::string> original = lines_of(read_bytes(write_three(other_dir)));
  ASSERT_EQ(original.size(), 3u);
  json last = json::parse(original[2]);
  last["trial"] = 1;
  original[2] = last.dump();
  EXPECT_EQ(parse_event_log(join_lines(original), "x").first_chain_error_line, 3);
}

TEST(ProtocolsLog, DroppedReorderedAndForgedLinesBreakTheChain) {
  TempDir dir;
  const std::vector<std::string> lines = lines_of(read_bytes(write_three(dir)));
  // Dropped line 2: line 2 now holds seq 2.
  EXPECT_EQ(parse_event_log(lines[0] + "\n" + lines[2] + "\n", "x").first_chain_error_line, 2);
  // Swapped lines 2 and 3.
  EXPECT_EQ(parse_event_log(lines[0] + "\n" + lines[2] + "\n" + lines[1] + "\n", "x").first_chain_error_line, 2);
  // Dropped first line.
  EXPECT_EQ(parse_event_log(lines[1] + "\n" + lines[2] + "\n", "x").first_chain_error_line, 1);
  // A line whose seq is right but chain is missing or not a string.
  json no_chain = json::parse(lines[1]);
  no_chain.erase("chain");
  EXPECT_EQ(parse_event_log(lines[0] + "\n" + no_chain.dump() + "\n" + lines[2] + "\n", "x").first_chain_error_line, 2);
  json number_chain = json::parse(lines[1]);
  number_chain["chain"] = 5;
  EXPECT_EQ(parse_event_log(lines[0] + "\n" + number_chain.dump() + "\n" + lines[2] + "\n", "x").first_chain_error_line,
            2);
  // An edit that recomputes its own chain still breaks the chain of the line after it.
  json recomputed = json::parse(lines[1]);
  recomputed["t"] = 9.0;
  recomputed.erase("chain");
  const std::string chain0 = json::parse(lines[0])["chain"];
  recomputed["chain"] = event_chain(chain0, recomputed);
  EXPECT_EQ(parse_event_log(lines[0] + "\n" + recomputed.dump() + "\n" + lines[2] + "\n", "x").first_chain_error_line,
            3);
  // The untouched log is consistent.
  EXPECT_EQ(parse_event_log(join_lines(lines), "x").first_chain_error_line, 0);
}

TEST(ProtocolsLog, TornTailIsReturnedNotParsed) {
  TempDir dir;
  const std::string path = write_three(dir);
  const std::string intact = read_bytes(path);
  const std::string torn = R"({"event":"trial_start","trial":1,"se)";
  write_bytes(path, intact + torn);
  const EventLogFile log = read_event_log(path);
  EXPECT_EQ(log.events.size(), 3u);
  ASSERT_TRUE(log.torn_tail.has_value());
  EXPECT_EQ(*log.torn_tail, torn);
  EXPECT_EQ(log.intact_bytes, intact.size());
  EXPECT_EQ(log.first_chain_error_line, 0);

  // A complete JSON object without its newline is torn too: the write may have been cut before it.
  const std::string whole = R"({"event":"x","seq":3})";
  const EventLogFile unterminated = parse_event_log(intact + whole, "x");
  EXPECT_EQ(unterminated.events.size(), 3u);
  ASSERT_TRUE(unterminated.torn_tail.has_value());
  EXPECT_EQ(*unterminated.torn_tail, whole);

  // Only a torn line.
  const EventLogFile only = parse_event_log("{\"ev", "x");
  EXPECT_TRUE(only.events.empty());
  ASSERT_TRUE(only.torn_tail.has_value());
  EXPECT_EQ(*only.torn_tail, "{\"ev");
  EXPECT_EQ(only.intact_bytes, 0u);
}

TEST(ProtocolsLog, CorruptMiddleLineIsAnInputErrorWithItsLine) {
  TempDir dir;
  const std::vector<std::string> lines = lines_of(read_bytes(write_three(dir)));
  for (const std::string& bad : {std::string("garbage"), std::string("[1, 2]"), std::string("\"text\""),
                                 std::string(""), std::string("{\"event\": ")}) {
    const std::string bytes = lines[0] + "\n" + bad + "\n" + lines[2] + "\n";
    try {
      parse_event_log(bytes, "results/s/p/events.jsonl");
      ADD_FAILURE() << "no error for line \"" << bad << "\"";
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.rfind("results/s/p/events.jsonl:2: ", 0), 0u) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
  }
  // A bad last line that is terminated is an error too (only an unterminated tail is "torn").
  EXPECT_THROW(parse_event_log(lines[0] + "\n" + lines[1] + "\n{oops\n", "x"), InputError);
  try {
    parse_event_log(lines[0] + "\n" + lines[1] + "\n{oops\n", "x");
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("x:3: ", 0), 0u) << error.what();
  }
}

TEST(ProtocolsLog, MissingFileIsAnInputError) {
  EXPECT_THROW(read_event_log("/nonexistent/fovlab/events.jsonl"), InputError);
}

TEST(ProtocolsLog, ContinuingALogKeepsTheChain) {
  TempDir dir;
  const std::string path = dir.file("events.jsonl");
  {
    EventLogWriter writer(path, "", 0);
    writer.append(
        {{"event", "session_header"}, {"schema_version", log_schema_version}, {"study", "s"}, {"participant", "p"}});
    writer.append({{"event", "trial_start"}, {"trial", 0}});
  }
  const EventLogFile first = read_event_log(path);
  ASSERT_EQ(first.events.size(), 2u);
  {
    EventLogWriter writer(path, first.last_chain, static_cast<int64_t>(first.events.size()));
    writer.append({{"event", "session_resumed"}});
    writer.append({{"event", "trial_start"}, {"trial", 0}});
  }
  const EventLogFile resumed = read_event_log(path);
  ASSERT_EQ(resumed.events.size(), 4u);
  EXPECT_EQ(resumed.first_chain_error_line, 0);
  EXPECT_EQ(resumed.events[2]["seq"], 2);
  EXPECT_EQ(resumed.events[3]["seq"], 3);
  EXPECT_EQ(resumed.events[2]["event"], "session_resumed");
  EXPECT_EQ(resumed.last_chain, resumed.events[3]["chain"].get<std::string>());

  // Continuing with a wrong seq or a wrong chain breaks the chain at the first appended line.
  const std::string wrong_seq = dir.file("wrong_seq.jsonl");
  write_bytes(wrong_seq, read_bytes(path));
  const EventLogFile base = read_event_log(wrong_seq);
  {
    EventLogWriter writer(wrong_seq, base.last_chain, 5);
    writer.append({{"event", "x"}});
  }
  EXPECT_EQ(read_event_log(wrong_seq).first_chain_error_line, 5);

  const std::string wrong_chain = dir.file("wrong_chain.jsonl");
  write_bytes(wrong_chain, read_bytes(path));
  {
    EventLogWriter writer(wrong_chain, "", 4);
    writer.append({{"event", "x"}});
  }
  EXPECT_EQ(read_event_log(wrong_chain).first_chain_error_line, 5);
}

TEST(ProtocolsLog, ContinuingAfterATornTailAppendsAfterTheIntactBytes) {
  // A resume truncates the torn tail first (intact_bytes) and then continues the chain.
  TempDir dir;
  const std::string path = write_three(dir);
  const std::string intact = read_bytes(path);
  write_bytes(path, intact + "{\"event\":\"tri");
  const EventLogFile torn = read_event_log(path);
  std::filesystem::resize_file(path, torn.intact_bytes);
  {
    EventLogWriter writer(path, torn.last_chain, static_cast<int64_t>(torn.events.size()));
    writer.append({{"event", "session_resumed"}});
  }
  const EventLogFile log = read_event_log(path);
  EXPECT_EQ(log.events.size(), 4u);
  EXPECT_FALSE(log.torn_tail.has_value());
  EXPECT_EQ(log.first_chain_error_line, 0);
}

TEST(ProtocolsLog, WriterCannotOpenAMissingFolder) {
  EXPECT_THROW(EventLogWriter("/nonexistent/fovlab/dir/events.jsonl", "", 0), InputError);
}

// --- the session record --------------------------------------------------------------------------------

// A log (bytes with seq and chain, as the writer makes them) of these events, parsed.
EventLogFile make_log(const std::vector<json>& events, const std::string& path = "results/s/p/events.jsonl") {
  std::string bytes, chain;
  int64_t seq = 0;
  for (json event : events) {
    event["seq"] = seq++;
    chain = event_chain(chain, event);
    event["chain"] = chain;
    bytes += event.dump() + "\n";
  }
  return parse_event_log(bytes, path);
}

json header() {
  return {{"event", "session_header"}, {"schema_version", log_schema_version}, {"study", "s"}, {"participant", "p"}};
}

std::vector<json> trial_events(int trial, double t, const std::string& answer,
                               std::optional<bool> attention = std::nullopt) {
  std::vector<json> events = {{{"event", "trial_start"}, {"trial", trial}, {"t", t}},
                              {{"event", "stimulus"}, {"trial", trial}, {"t", t + 0.1}, {"interval", 0}},
                              {{"event", "stimulus"}, {"trial", trial}, {"t", t + 0.2}, {"interval", 1}},
                              {{"event", "response"}, {"trial", trial}, {"t", t + 0.3}, {"answer", answer}}};
  if (attention) events.push_back({{"event", "attention_check"}, {"trial", trial}, {"correct", *attention}});
  events.push_back({{"event", "trial_end"}, {"trial", trial}, {"t", t + 0.4}});
  return events;
}

void append(std::vector<json>& to, const std::vector<json>& events) {
  to.insert(to.end(), events.begin(), events.end());
}

std::string record_error(const EventLogFile& log) {
  try {
    read_session_record(log);
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST(ProtocolsLog, RecordOfACompleteSession) {
  std::vector<json> events = {header()};
  append(events, trial_events(0, 1.0, "same"));
  append(events, trial_events(1, 2.0, "different", true));
  events.push_back({{"event", "session_end"}, {"reason", "completed"}, {"t", 9.5}});
  const SessionRecord record = read_session_record(make_log(events));
  EXPECT_EQ(record.header["event"], "session_header");
  ASSERT_EQ(record.trials.size(), 2u);
  EXPECT_EQ(record.trials[0].index, 0);
  EXPECT_EQ(record.trials[1].index, 1);
  EXPECT_EQ(record.trials[0].stimuli.size(), 2u);
  ASSERT_TRUE(record.trials[0].stimuli[1].stamp.t);
  EXPECT_DOUBLE_EQ(*record.trials[0].stimuli[1].stamp.t, 1.2);  // the second, in order
  ASSERT_EQ(record.trials[0].responses.size(), 1u);
  EXPECT_EQ(record.trials[0].responses[0].answer, "same");
  EXPECT_EQ(record.trials[0].start.trial, 0);
  EXPECT_EQ(record.trials[0].start.stamp.t, 1.0);  // the trial_start event
  EXPECT_EQ(record.trials[0].end.trial, 0);
  EXPECT_EQ(record.trials[0].end.stamp.t, 1.4);  // the trial_end event
  EXPECT_FALSE(record.trials[0].attention_check.has_value());
  ASSERT_TRUE(record.trials[1].attention_check.has_value());
  EXPECT_EQ(record.attention_errors, 0);
  EXPECT_TRUE(record.ended);
  EXPECT_EQ(record.end_reason, "completed");
  EXPECT_FALSE(record.excluded);
  EXPECT_EQ(record.next_trial, 2);
  EXPECT_EQ(record.incomplete_trial, -1);
  EXPECT_DOUBLE_EQ(record.last_time_s, 9.5);
}

TEST(ProtocolsLog, RecordKeepsOnlyCompleteTrials) {
  std::vector<json> events = {header()};
  append(events, trial_events(0, 1.0, "same"));
  append(events, trial_events(1, 2.0, "same"));
  events.push_back({{"event", "trial_start"}, {"trial", 2}, {"t", 3.0}});
  events.push_back({{"event", "stimulus"}, {"trial", 2}, {"t", 3.1}});
  events.push_back({{"event", "response"}, {"trial", 2}, {"t", 3.2}, {"answer", "same"}});
  const SessionRecord record = read_session_record(make_log(events));
  ASSERT_EQ(record.trials.size(), 2u);
  EXPECT_EQ(record.trials.back().index, 1);
  EXPECT_EQ(record.incomplete_trial, 2);
  EXPECT_EQ(record.next_trial, 2);  // the cut-off trial runs again
  EXPECT_FALSE(record.ended);
  EXPECT_DOUBLE_EQ(record.last_time_s, 3.2);
}

TEST(ProtocolsLog, SessionResumedDiscardsTheOpenTrial) {
  std::vector<json> events = {header()};
  append(events, trial_events(0, 1.0, "same"));
  events.push_back({{"event", "trial_start"}, {"trial", 1}, {"t", 2.0}});
  events.push_back({{"event", "response"}, {"trial", 1}, {"t", 2.1}, {"answer", "first attempt"}});
  events.push_back({{"event", "session_resumed"}, {"t", 0.5}});
  // Before the trial runs again, the resumed session is at trial 1 with nothing open.
  const SessionRecord between = read_session_record(make_log(events));
  EXPECT_EQ(between.incomplete_trial, -1);
  EXPECT_EQ(between.next_trial, 1);
  EXPECT_EQ(between.trials.size(), 1u);

  append(events, trial_events(1, 3.0, "second attempt"));
  const SessionRecord record = read_session_record(make_log(events));
  ASSERT_EQ(record.trials.size(), 2u);
  ASSERT_EQ(record.trials[1].responses.size(), 1u);
  EXPECT_EQ(record.trials[1].responses[0].answer, "second attempt");
  EXPECT_EQ(record.incomplete_trial, -1);
  EXPECT_EQ(record.next_trial, 2);

  // An event of the discarded trial after the resume, without a new trial_start, contradicts the log.
  std::vector<json> stray = {header()};
  stray.push_back({{"event", "trial_start"}, {"trial", 0}});
  stray.push_back({{"event", "session_resumed"}});
  stray.push_back({{"event", "trial_end"}, {"trial", 0}});
  const std::string message = record_error(make_log(stray));
  EXPECT_EQ(message.rfind("results/s/p/events.jsonl:4: ", 0), 0u) << message;
}

TEST(ProtocolsLog, AttentionErrorsCountOnlyCompleteTrials) {
  std::vector<json> events = {header()};
  append(events, trial_events(0, 1.0, "different", false));  // wrong
  append(events, trial_events(1, 2.0, "same", true));        // right
  append(events, trial_events(2, 3.0, "different", false));  // wrong
  events.push_back({{"event", "trial_start"}, {"trial", 3}});
  events.push_back({{"event", "attention_check"}, {"trial", 3}, {"correct", false}});  // wrong but cut off
  SessionRecord record = read_session_record(make_log(events));
  EXPECT_EQ(record.attention_errors, 2);
  EXPECT_EQ(record.incomplete_trial, 3);
  EXPECT_EQ(record.next_trial, 3);

  // A wrong check of a trial cut off and then run again correctly counts once, as the rerun says.
  events.push_back({{"event", "session_resumed"}});
  append(events, trial_events(3, 5.0, "same", true));
  events.push_back({{"event", "excluded"}, {"t", 6.0}});
  record = read_session_record(make_log(events));
  EXPECT_EQ(record.attention_errors, 2);
  EXPECT_EQ(record.next_trial, 4);
  EXPECT_TRUE(record.excluded);
}

TEST(ProtocolsLog, NextTrialIsTheFirstMissingIndex) {
  std::vector<json> events = {header()};
  append(events, trial_events(0, 1.0, "same"));
  append(events, trial_events(1, 2.0, "same"));
  append(events, trial_events(3, 4.0, "same"));
  const SessionRecord record = read_session_record(make_log(events));
  ASSERT_EQ(record.trials.size(), 3u);
  EXPECT_EQ(record.trials[2].index, 3);
  EXPECT_EQ(record.next_trial, 2);

  // Trials come back ordered by index.
  std::vector<json> out_of_order = {header()};
  append(out_of_order, trial_events(1, 1.0, "a"));
  append(out_of_order, trial_events(0, 2.0, "b"));
  const SessionRecord sorted = read_session_record(make_log(out_of_order));
  ASSERT_EQ(sorted.trials.size(), 2u);
  EXPECT_EQ(sorted.trials[0].index, 0);
  EXPECT_EQ(sorted.trials[1].index, 1);
  EXPECT_EQ(sorted.next_trial, 2);
  // A trial completes once: a second record of an index is a forged or spliced log (issue 14).
  append(out_of_order, trial_events(1, 3.0, "c"));
  const std::string message = record_error(make_log(out_of_order));
  EXPECT_NE(message.find("trial 1 is complete twice"), std::string::npos) << message;
}

TEST(ProtocolsLog, BreaksAndSliderEventsBelongToTheirTrial) {
  std::vector<json> events = {header()};
  events.push_back({{"event", "trial_start"}, {"trial", 0}});
  events.push_back({{"event", "slider_saved"}, {"trial", 0}, {"level", 16}});
  events.push_back({{"event", "break"}, {"trial", 0}, {"seconds", 5}});
  events.push_back({{"event", "trial_end"}, {"trial", 0}});
  events.push_back({{"event", "break"}, {"t", 7.0}});  // a rest between blocks: no trial
  const SessionRecord record = read_session_record(make_log(events));
  ASSERT_EQ(record.trials.size(), 1u);
  ASSERT_EQ(record.trials[0].slider_saved.size(), 1u);
  EXPECT_EQ(record.trials[0].slider_saved[0].level, 16.0);
  ASSERT_EQ(record.trials[0].breaks.size(), 1u);
  EXPECT_EQ(record.trials[0].breaks[0].trial, 0);
  EXPECT_DOUBLE_EQ(record.last_time_s, 7.0);
}

TEST(ProtocolsLog, ContradictoryEventsAreInputErrorsWithTheirLine) {
  {
    std::vector<json> events = {header(), {{"event", "trial_end"}, {"trial", 0}}};
    const std::string message = record_error(make_log(events));
    EXPECT_EQ(message.rfind("results/s/p/events.jsonl:2: ", 0), 0u) << message;
    EXPECT_NE(message.find("trial_end"), std::string::npos) << message;
  }
  {
    std::vector<json> events = {
        header(), {{"event", "trial_start"}, {"trial", 0}}, {{"event", "response"}, {"trial", 1}}};
    const std::string message = record_error(make_log(events));
    EXPECT_EQ(message.rfind("results/s/p/events.jsonl:3: ", 0), 0u) << message;
  }
  {
    std::vector<json> events = {header(), {{"event", "trial_start"}}};
    const std::string message = record_error(make_log(events));
    EXPECT_EQ(message.rfind("results/s/p/events.jsonl:2: ", 0), 0u) << message;
  }
  {
    std::vector<json> events = {header(), {{"trial", 0}}};
    const std::string message = record_error(make_log(events));
    EXPECT_EQ(message.rfind("results/s/p/events.jsonl:2: ", 0), 0u) << message;
  }
}

TEST(ProtocolsLog, HeaderSchemaChecks) {
  // No events at all.
  EXPECT_THROW(read_session_record(make_log({})), InputError);
  // First event not a header.
  {
    const std::string message = record_error(make_log({{{"event", "trial_start"}, {"trial", 0}}}));
    EXPECT_EQ(message.rfind("results/s/p/events.jsonl:1: ", 0), 0u) << message;
    EXPECT_NE(message.find("session_header"), std::string::npos) << message;
  }
  // schema_version missing.
  {
    const std::string message = record_error(make_log({{{"event", "session_header"}}}));
    EXPECT_EQ(message.rfind("results/s/p/events.jsonl:1: ", 0), 0u) << message;
    EXPECT_NE(message.find("schema_version"), std::string::npos) << message;
  }
  // schema_version of another version, or not an integer.
  for (const json& version : {json(log_schema_version + 1), json(0), json("1"), json(1.5), json(nullptr)}) {
    const std::string message = record_error(make_log({{{"event", "session_header"}, {"schema_version", version}}}));
    EXPECT_EQ(message.rfind("results/s/p/events.jsonl:1: ", 0), 0u) << message;
    EXPECT_NE(message.find("schema_version"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // The version this build writes is accepted.
  EXPECT_NO_THROW(read_session_record(make_log({header()})));
  EXPECT_EQ(log_schema_version, 13);
}

TEST(ProtocolsLog, HeaderSchemaVersionIsNotWrapped) {
  // 2^32 + 1 is not schema version 1 (reading it as a 32-bit int would wrap it to 1).
  const std::string message =
      record_error(make_log({{{"event", "session_header"}, {"schema_version", int64_t{4294967297}}}}));
  EXPECT_NE(message.find("schema_version"), std::string::npos) << message;
}

TEST(ProtocolsLog, RecordFromAWrittenFile) {
  TempDir dir;
  const std::string path = dir.file("events.jsonl");
  {
    EventLogWriter writer(path, "", 0);
    writer.append(header());
    for (const json& event : trial_events(0, 1.0, "same")) writer.append(event);
    writer.append({{"event", "trial_start"}, {"trial", 1}, {"t", 2.0}});
  }
  write_bytes(path, read_bytes(path) + "{\"event\":\"stimu");  // a crash mid-write
  const EventLogFile log = read_event_log(path);
  EXPECT_TRUE(log.torn_tail.has_value());
  const SessionRecord record = read_session_record(log);
  EXPECT_EQ(record.trials.size(), 1u);
  EXPECT_EQ(record.incomplete_trial, 1);
  EXPECT_EQ(record.next_trial, 1);
  EXPECT_DOUBLE_EQ(record.last_time_s, 2.0);
}

}  // namespace
}  // namespace fovlab
