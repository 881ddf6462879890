// The typed log events (study/log/log_events.h): every struct survives JSON both ways, and to_json
// writes exactly the text the writer's JSON literals wrote before the types (log schema 3 bytes).
#include "study/log/log_events.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

#include "core/input_error.h"
#include "study/log/event_log.h"
#include "study/log/log_event_fields.h"

namespace fovlab {
namespace {

// The "t" SessionRun::log adds to an event that has none.
nlohmann::json logged(nlohmann::json event, double t) {
  if (!event.contains("t")) event["t"] = t;
  return event;
}

template <typename Event, typename Parse>
void expect_round_trip(const Event& event, Parse parse) {
  const nlohmann::json json = to_json(event);
  EXPECT_EQ(json.at("event"), Event::kind);
  EXPECT_EQ(parse(json, FieldCheck::strict), event) << json.dump();
  // Through the text, as a reader sees it.
  EXPECT_EQ(parse(nlohmann::json::parse(json.dump()), FieldCheck::strict), event) << json.dump();
}

EventStamp stamp(double t, int64_t seq) { return EventStamp{t, seq}; }

TEST(LogEvents, EveryEventRoundTrips) {
  SessionHeaderEvent header;
  header.stamp = stamp(0.0, 0);
  header.schema_version = 3;
  header.lab_key_id = "0123456789abcdef";
  header.fovlab_version = "1.2.3";
  header.study = "demo";
  header.participant = "P001";
  header.study_seed = 18446744073709551615ull;
  header.session_seed = 42;
  header.config_path = "studies/demo.toml";
  header.config_hash = "00ff";
  header.config_toml = "name = \"demo\"\n";
  header.protocol = "2afc";
  header.trial_count = 12;
  header.scene_hashes = {{"sponza", "abcd"}};
  header.stimuli = nlohmann::json::array({{{"method", "gt"}, {"level", nullptr}}});
  header.device = {{"name", "llvmpipe"}, {"driver", "mesa"}};
  header.display = {{"width_px", 640}, {"refresh_hz", 60.0}};
  header.presenter = "headless";
  header.gaze = "synthetic:seed=1";
  header.observer = {{"model", "logistic"}, {"threshold", 0.5}};
  header.started_utc = "2026-01-01T00:00:00Z";
  expect_round_trip(header, parse_session_header);
  header.lab_key_id.reset();
  header.observer = "human";
  expect_round_trip(header, parse_session_header);
  EXPECT_FALSE(to_json(header).contains("conditions_csv"));  // written only with a conditions file
  header.conditions_csv = "variant,max_steps\nblur,4\n";
  expect_round_trip(header, parse_session_header);

  expect_round_trip(SessionResumedEvent{stamp(3.5, 40), 7, 6, "events.jsonl.torn-1", "mouse", "2026-01-02T00:00:00Z"},
                    parse_session_resumed);
  expect_round_trip(SessionResumedEvent{stamp(3.5, 40), 7, std::nullopt, std::nullopt, "mouse", "x"},
                    parse_session_resumed);
  expect_round_trip(InstructionsEvent{stamp(1.25, 1), 0.5}, parse_instructions);
  expect_round_trip(BlockStartEvent{stamp(2.0, 2), 1, "blur", "sponza"}, parse_block_start);
  expect_round_trip(BreakEvent{stamp(9.0, 3), BreakEvent::rest, std::nullopt, 3.0, 6.0}, parse_break);
  expect_round_trip(BreakEvent{stamp(9.0, 3), BreakEvent::attention_check, 4, 3.0, 6.0}, parse_break);

  TrialStartEvent start{stamp(4.0, 5), 3,      1, "level=32", "foveated",   32.0,
                        false,         {2, 0}, 0, true,       std::nullopt, std::nullopt};
  expect_round_trip(start, parse_trial_start);
  start.level.reset();
  start.reference_first.reset();
  start.ramp_toward_reference = false;
  expect_round_trip(start, parse_trial_start);
  start.ramp_toward_reference.reset();
  start.slider_start = 2;
  expect_round_trip(start, parse_trial_start);
  start.practice = true;  // written only when true
  expect_round_trip(start, parse_trial_start);
  EXPECT_EQ(to_json(start)["practice"], true);
  start.practice = false;
  EXPECT_FALSE(to_json(start).contains("practice"));

  StimulusEvent stimulus;
  stimulus.stamp = stamp(5.0, 6);
  stimulus.trial = 3;
  stimulus.step = 1;
  stimulus.stimulus = 2;
  stimulus.onset_s = 4.5;
  stimulus.present_s = {4.5, 4.516, 4.533};
  stimulus.frame = {0, 0, 1};
  stimulus.hash = {"a1", "a1", "b2"};
  stimulus.gaze = {{{320.25, 240.5}}, {{321.0, 240.0}}, {{321.0, 240.0}}};
  stimulus.invalid_gaze = {{2, "blink"}};
  stimulus.dropped_frames = 1;
  stimulus.gaze_acquired_s = std::vector<std::optional<double>>{4.49, 4.5, std::nullopt};
  stimulus.gaze_age_s = std::vector<std::optional<double>>{0.01, 0.016, std::nullopt};
  stimulus.present_clock = "virtual";
  expect_round_trip(stimulus, parse_stimulus);
  stimulus.gaze_acquired_s.reset();  // schema 2: no latency fields
  stimulus.gaze_age_s.reset();
  stimulus.present_clock.reset();
  expect_round_trip(stimulus, parse_stimulus);

  expect_round_trip(ResponseEvent{stamp(6.0, 7), 3, 0, "different", "d", 0.75}, parse_response);
  expect_round_trip(ResponseEvent{stamp(6.0, 7), 3, 0, "", "", 2.0}, parse_response);
  expect_round_trip(SliderSavedEvent{stamp(7.0, 8), 3, 2, 5, 12.5}, parse_slider_saved);
  expect_round_trip(AttentionCheckEvent{stamp(7.5, 9), 3, false, 2}, parse_attention_check);
  expect_round_trip(TrialEndEvent{stamp(8.0, 10), 3}, parse_trial_end);
  expect_round_trip(ExcludedEvent{stamp(8.0, 11), 2, 2}, parse_excluded);
  expect_round_trip(SessionPausedEvent{stamp(8.5, 12), "window closed"}, parse_session_paused);
  expect_round_trip(SessionEndEvent{stamp(9.0, 13), SessionEndEvent::completed, 12}, parse_session_end);
  expect_round_trip(SealEvent{stamp(9.0, 14), 12, std::string(64, 'a')}, parse_seal);
}

// The literals the writer used before the types (protocols/session/session_run.cpp, session.cpp,
// session_header.cpp at 58feb1a), with fixed inputs: to_json must give the same text.
TEST(LogEvents, ToJsonWritesTheBytesTheOldLiteralsWrote) {
  const double t = 12.345678901234;
  const auto same = [](const nlohmann::json& typed, const nlohmann::json& old) { EXPECT_EQ(typed.dump(), old.dump()); };

  same(logged(to_json(InstructionsEvent{{}, 0.125}), t), logged({{"event", "instructions"}, {"shown_s", 0.125}}, t));
  same(logged(to_json(BreakEvent{{}, BreakEvent::rest, std::nullopt, 1.5, 600.0166666}), t),
       logged({{"event", "break"}, {"reason", "rest"}, {"start_s", 1.5}, {"duration_s", 600.0166666}}, t));
  same(logged(to_json(BlockStartEvent{{}, 1, "blur", "sponza"}), t),
       logged({{"event", "block_start"}, {"block", 1}, {"name", "blur"}, {"scene", "sponza"}}, t));
  const std::vector<int> sequence = {4, 0};
  for (int kind = 0; kind < 3; ++kind) {
    for (const bool with_level : {false, true}) {
      TrialStartEvent start{{},   7,        1, "level=32",   "foveated",   std::nullopt,
                            true, sequence, 0, std::nullopt, std::nullopt, std::nullopt};
      nlohmann::json old = {{"event", "trial_start"},
                            {"trial", 7},
                            {"block", 1},
                            {"condition", "level=32"},
                            {"variant", "foveated"},
                            {"attention_check", true},
                            {"sequence", sequence},
                            {"reference", 0}};
      if (with_level) {
        start.level = 32.0;
        old["level"] = 32.0;
      }
      if (kind == 0) start.ramp_toward_reference = false, old["ramp_toward_reference"] = false;
      else if (kind == 1) start.slider_start = 3, old["slider_start"] = 3;
      else start.reference_first = true, old["reference_first"] = true;
      same(logged(to_json(start), t), logged(old, t));
    }
  }

  // A stimulus event as present_stimulus built it: arrays, an invalid sample, null latency.
  nlohmann::json present_s = nlohmann::json::array(), frames = nlohmann::json::array(),
                 hashes = nlohmann::json::array(), gaze = nlohmann::json::array(), invalid = nlohmann::json::array(),
                 acquired = nlohmann::json::array(), ages = nlohmann::json::array();
  StimulusEvent stimulus;
  stimulus.trial = 7;
  stimulus.step = 1;
  stimulus.stimulus = 4;
  stimulus.onset_s = 2.0 / 3.0;
  std::vector<std::optional<double>> typed_acquired, typed_ages;
  for (int refresh = 0; refresh < 4; ++refresh) {
    const double shown_at = 2.0 / 3.0 + refresh / 60.0;
    const double x = 320.25 + refresh, y = 0.01 * refresh;
    const bool valid = refresh != 2;
    if (!valid) invalid.push_back({{"i", present_s.size()}, {"reason", "blink"}});
    if (!valid) stimulus.invalid_gaze.push_back({static_cast<int>(stimulus.present_s.size()), "blink"});
    present_s.push_back(shown_at);
    stimulus.present_s.push_back(shown_at);
    frames.push_back(refresh / 2);
    stimulus.frame.push_back(refresh / 2);
    hashes.push_back("00112233aabbccd" + std::to_string(refresh));
    stimulus.hash.push_back("00112233aabbccd" + std::to_string(refresh));
    gaze.push_back({x, y});
    stimulus.gaze.push_back({x, y});
    if (refresh != 3) {
      acquired.push_back(shown_at - 0.04);
      ages.push_back(shown_at - (shown_at - 0.04));
      typed_acquired.push_back(shown_at - 0.04);
      typed_ages.push_back(shown_at - (shown_at - 0.04));
    } else {
      acquired.push_back(nullptr);
      ages.push_back(nullptr);
      typed_acquired.push_back(std::nullopt);
      typed_ages.push_back(std::nullopt);
    }
  }
  stimulus.stamp.t = t;
  stimulus.dropped_frames = 2;
  stimulus.gaze_acquired_s = typed_acquired;
  stimulus.gaze_age_s = typed_ages;
  stimulus.present_clock = "virtual";
  same(logged(to_json(stimulus), 99.0), logged({{"event", "stimulus"},
                                                {"trial", 7},
                                                {"step", 1},
                                                {"stimulus", 4},
                                                {"onset_s", 2.0 / 3.0},
                                                {"t", t},
                                                {"present_s", present_s},
                                                {"frame", frames},
                                                {"hash", hashes},
                                                {"gaze", gaze},
                                                {"invalid_gaze", invalid},
                                                {"dropped_frames", 2},
                                                {"gaze_acquired_s", acquired},
                                                {"gaze_age_s", ages},
                                                {"present_clock", "virtual"}},
                                               99.0));

  same(logged(to_json(ResponseEvent{{t}, 7, 0, "different", "d", 0.6180339887}), 99.0), logged({{"event", "response"},
                                                                                                {"trial", 7},
                                                                                                {"step", 0},
                                                                                                {"answer", "different"},
                                                                                                {"key", "d"},
                                                                                                {"rt_s", 0.6180339887},
                                                                                                {"t", t}},
                                                                                               99.0));
  same(logged(to_json(SliderSavedEvent{{}, 7, 2, 5, 0.0}), t),
       logged({{"event", "slider_saved"}, {"trial", 7}, {"ladder_index", 2}, {"stimulus", 5}, {"level", 0.0}}, t));
  same(logged(to_json(AttentionCheckEvent{{}, 7, false, 1}), t),
       logged({{"event", "attention_check"}, {"trial", 7}, {"correct", false}, {"errors", 1}}, t));
  same(
      logged(to_json(BreakEvent{{}, BreakEvent::attention_check, 7, 3.25, 30.0}), t),
      logged({{"event", "break"}, {"trial", 7}, {"reason", "attention_check"}, {"start_s", 3.25}, {"duration_s", 30.0}},
             t));
  same(logged(to_json(TrialEndEvent{{}, 7}), t), logged({{"event", "trial_end"}, {"trial", 7}}, t));
  same(logged(to_json(ExcludedEvent{{}, 2, 2}), t),
       logged({{"event", "excluded"}, {"errors", 2}, {"max_errors", 2}}, t));
  same(logged(to_json(SessionEndEvent{{}, SessionEndEvent::excluded, 8}), t),
       logged({{"event", "session_end"}, {"reason", "excluded"}, {"completed_trials", 8}}, t));
  const size_t trials = 12;
  same(logged(to_json(SessionEndEvent{{}, SessionEndEvent::completed, static_cast<int>(trials)}), t),
       logged({{"event", "session_end"}, {"reason", "completed"}, {"completed_trials", trials}}, t));
  same(logged(to_json(SessionPausedEvent{{}, "the window was closed"}), t),
       logged({{"event", "session_paused"}, {"reason", "the window was closed"}}, t));
  same(logged(to_json(SealEvent{{}, 12, {}}), t), logged({{"event", "seal"}, {"trials_complete", 12}}, t));
  same(to_json(SealEvent{{t}, 12, {}}), {{"event", "seal"}, {"t", t}, {"trials_complete", 12}});

  for (const bool fresh : {true, false}) {
    SessionResumedEvent resumed{{}, 5, std::nullopt, std::nullopt, "synthetic:seed=1", "2026-01-01T00:00:00Z"};
    nlohmann::json old = {{"event", "session_resumed"},
                          {"next_trial", 5},
                          {"started_utc", "2026-01-01T00:00:00Z"},
                          {"gaze", "synthetic:seed=1"}};
    old["discarded_trial"] = fresh ? nlohmann::json() : nlohmann::json(4);
    old["torn_line_set_aside"] = fresh ? nlohmann::json() : nlohmann::json("events.jsonl.torn-1");
    if (!fresh) {
      resumed.discarded_trial = 4;
      resumed.torn_line_set_aside = "events.jsonl.torn-1";
    }
    same(logged(to_json(resumed), t), logged(old, t));
  }

  // The header as make_session_header built it, then run_session's lab_key_id.
  const uint64_t study_seed = 1234567890123ull, session_seed = 18446744073709551557ull;
  const nlohmann::json scenes = {{"sponza", "0011"}, {"/abs/cornell.scene", "2233"}};
  const nlohmann::json stimuli =
      nlohmann::json::array({{{"method", "gt"}, {"is_reference", true}, {"level", nullptr}}});
  const nlohmann::json device = {{"name", "llvmpipe"}, {"type", "cpu"}, {"api_version", "1.3.255"}, {"driver", "mesa"}};
  const nlohmann::json display = {
      {"width_px", 640},   {"height_px", 480},   {"refresh_hz", 60.0},           {"measured_refresh_hz", 59.94},
      {"width_mm", 520.0}, {"height_mm", 290.0}, {"viewing_distance_mm", 600.0}, {"fullscreen", false}};
  for (const bool keyed : {false, true}) {
    nlohmann::json old = {{"event", "session_header"},
                          {"schema_version", 3},
                          {"fovlab_version", "0.9"},
                          {"study", "demo"},
                          {"participant", "P001"},
                          {"study_seed", study_seed},
                          {"session_seed", session_seed},
                          {"config_path", "demo.toml"},
                          {"config_hash", "abcd"},
                          {"config_toml", "name = \"demo\"\n[display]\n"},
                          {"protocol", "2afc"},
                          {"trial_count", trials},
                          {"scene_hashes", scenes},
                          {"device", device},
                          {"display", display},
                          {"presenter", "headless"},
                          {"gaze", "synthetic"},
                          {"observer", "human"},
                          {"started_utc", "2026-01-01T00:00:00Z"},
                          {"t", 0.0}};
    old["stimuli"] = stimuli;
    old["lab_key_id"] = keyed ? nlohmann::json("0123456789abcdef") : nlohmann::json();
    SessionHeaderEvent header;
    header.stamp.t = 0.0;
    header.schema_version = 3;
    header.fovlab_version = "0.9";
    header.study = "demo";
    header.participant = "P001";
    header.study_seed = study_seed;
    header.session_seed = session_seed;
    header.config_path = "demo.toml";
    header.config_hash = "abcd";
    header.config_toml = "name = \"demo\"\n[display]\n";
    header.protocol = "2afc";
    header.trial_count = static_cast<int64_t>(trials);
    header.scene_hashes = scenes;
    header.device = device;
    header.display = display;
    header.presenter = "headless";
    header.gaze = "synthetic";
    header.observer = "human";
    header.started_utc = "2026-01-01T00:00:00Z";
    header.stimuli = stimuli;
    if (keyed) header.lab_key_id = "0123456789abcdef";
    same(to_json(header), old);
  }
}

// Logs an earlier fovlab wrote (schema 2, plain and keyed): every event reads strictly, and its
// struct writes back exactly the text it was read from (less the writer's chain and MAC).
TEST(LogEvents, LogsOfAnEarlierFovlabWriteBackTheSameText) {
  for (const char* name : {"22_schema2_rating_sealed.jsonl", "23_schema2_rating_keyed_seal.jsonl"}) {
    const EventLogFile log = read_event_log(std::string(FOVLAB_SOURCE_DIR) + "/tests/fuzz/corpus/log/" + name);
    ASSERT_GT(log.events.size(), 10u) << name;
    std::set<std::string> kinds;
    for (nlohmann::json event : log.events) {
      const LogEvent typed = parse_log_event(event);
      kinds.insert(event_kind(event));
      event.erase("chain");
      event.erase("mac");
      EXPECT_EQ(to_json(typed).dump(), event.dump()) << name;
    }
    EXPECT_EQ(kinds.size(), 10u)
        << name;  // header, instructions, block, trial, stimulus, response, check, end, session end, seal
  }
  EXPECT_THROW(parse_log_event({{"event", "interval"}}), InputError);
  EXPECT_THROW(parse_log_event({{"trial", 1}}), InputError);
}

TEST(LogEvents, StrictParseNamesTheFieldLenientKeepsTheDefault) {
  const nlohmann::json response = {{"event", "response"}, {"trial", 3},     {"step", 0}, {"answer", "same"},
                                   {"key", "s"},          {"rt_s", "fast"}, {"t", 1.0},  {"seq", 4}};
  try {
    parse_response(response);
    FAIL() << "a string rt_s was accepted";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "response: rt_s: expected a number, got \"fast\"");
  }
  const ResponseEvent lenient = parse_response(response, FieldCheck::lenient);
  EXPECT_FALSE(lenient.rt_s);  // unknown, never a made-up 0
  // A field the log does not have stays unknown, and is not written back.
  const ResponseEvent without_rt =
      parse_response({{"event", "response"}, {"trial", 1}, {"step", 0}, {"answer", "same"}, {"key", "s"}, {"t", 1.0}});
  EXPECT_FALSE(without_rt.rt_s);
  EXPECT_FALSE(to_json(without_rt).contains("rt_s"));
  EXPECT_FALSE(parse_attention_check({{"event", "attention_check"}, {"trial", 2}, {"errors", 0}}).correct);
  EXPECT_EQ(lenient.answer, "same");
  EXPECT_EQ(lenient.stamp.seq, 4);

  nlohmann::json stimulus = to_json(StimulusEvent{});
  stimulus["gaze"] = nlohmann::json::array({{1.0}});
  EXPECT_THROW(parse_stimulus(stimulus), InputError);
  stimulus["gaze"] = nlohmann::json::array();
  stimulus["frame"] = nlohmann::json::array({0, 1.5});
  try {
    parse_stimulus(stimulus);
    FAIL() << "a fractional frame was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("stimulus: frame: expected an array of 32-bit integers"),
              std::string::npos)
        << error.what();
  }
  EXPECT_TRUE(parse_stimulus(stimulus, FieldCheck::lenient).frame.empty());
  EXPECT_THROW(parse_trial_end(nlohmann::json::array()), InputError);
  EXPECT_THROW(parse_trial_end({{"event", "trial_end"}, {"trial", 4294967296ll}}), InputError);
  // Missing fields keep their defaults (older schemas lack some).
  const StimulusEvent schema2 = parse_stimulus({{"event", "stimulus"}, {"trial", 1}});
  EXPECT_FALSE(schema2.present_clock);
  EXPECT_FALSE(schema2.gaze_age_s);
}

TEST(LogEvents, FieldTypeChecksRefuseWhatTheReadersRefuse) {
  EXPECT_EQ(check_log_field_types(to_json(TrialEndEvent{{1.0, 3}, 2})), "");
  EXPECT_EQ(check_log_field_types({{"trial", "2"}}), "an event has a field of the wrong type (trial: \"2\")");
  EXPECT_EQ(check_log_field_types({{"level", nullptr}}), "");
  EXPECT_NE(check_log_field_types({{"sequence", {1, 4294967296ll}}}), "");
  EXPECT_NE(check_log_field_types({{"gaze_age_s", {1.0, "x"}}}), "");
  EXPECT_NE(check_log_field_types({{"present_clock", 1}}), "");
  EXPECT_NE(check_log_field_types({{"late_frames", "2"}}), "");
  EXPECT_EQ(check_log_field_types({{"rt_s", "fast"}}), "") << "rt_s is not a checked field (the fast scan skips it)";
}

// The keys both readers type-check on every line (and the scan keeps) are those the event tables
// mark: the same set, and the same types, as the hand-written checks had before the tables.
TEST(LogEvents, TheTablesTypedKeysAreTheCheckedOnes) {
  using log_fields::LineType;
  std::map<std::string, LineType> typed, kept;
  for (const log_fields::ScannedKey& key : log_fields::scanned_keys())
    (key.scan == log_fields::Scan::typed ? typed : kept)[std::string(key.key)] = key.type;
  const std::map<std::string, LineType> expected = {
      {"trial", LineType::small_int},
      {"block", LineType::small_int},
      {"step", LineType::small_int},
      {"track", LineType::small_int},
      {"dropped_frames", LineType::small_int},
      {"late_frames", LineType::small_int},  // schema 12: the report counts them
      {"condition", LineType::string},
      {"variant", LineType::string},
      {"answer", LineType::string},
      {"name", LineType::string},
      {"scene", LineType::string},
      {"present_clock", LineType::string},
      {"level", LineType::number_or_null},
      {"attention_check", LineType::boolean},
      {"reference_first", LineType::boolean},
      {"ramp_toward_reference", LineType::boolean},
      {"correct", LineType::boolean},
      {"practice", LineType::boolean},
      {"sequence", LineType::small_int_array},
      {"gaze_acquired_s", LineType::number_or_null_array},
      {"gaze_age_s", LineType::number_or_null_array},
  };
  EXPECT_EQ(typed, expected);
  EXPECT_EQ(kept, (std::map<std::string, LineType>{{"present_s", LineType::numbers_lenient},
                                                  {"invalid_gaze", LineType::invalid_gaze_lenient},
                                                  {"right_eye_invalid_gaze", LineType::invalid_gaze_lenient}}));
  for (const log_fields::ScannedKey& key : log_fields::scanned_keys())
    EXPECT_EQ(log_fields::scanned_keys().at(size_t(log_fields::scanned_key_index(key.key))).key, key.key);
  EXPECT_EQ(log_fields::scanned_key_index("rt_s"), -1);
  // Each key's check, as its line type says.
  EXPECT_NE(check_log_field_types({{"block", 1.5}}), "");
  EXPECT_NE(check_log_field_types({{"practice", 1}}), "");
  EXPECT_NE(check_log_field_types({{"name", nullptr}}), "");
  EXPECT_NE(check_log_field_types({{"event", 3}}), "");
  EXPECT_NE(check_log_field_types({{"track", 4294967296ll}}), "");
  EXPECT_EQ(check_log_field_types({{"present_s", "x"}}), "") << "present_s is read leniently, not checked";
  EXPECT_EQ(check_log_field_types({{"invalid_gaze", "x"}}), "") << "invalid_gaze is read leniently, not checked";
  EXPECT_EQ(
      check_log_field_types({{"gaze_age_s", {nullptr, 0.5}}, {"correct", true}, {"sequence", nlohmann::json::array()}}),
      "");
}

// Who answered: "human", or "simulated" for a model; anything else (a missing field too) is refused,
// never taken for a person.
TEST(LogEvents, ObserverKindIsHumanOrSimulatedAndNothingElse) {
  EXPECT_EQ(observer_kind({{"observer", "human"}}), "human");
  EXPECT_EQ(observer_kind({{"observer", {{"threshold", 9.0}}}}), "simulated");
  EXPECT_THROW(observer_kind(nlohmann::json::object()), InputError);
  EXPECT_THROW(observer_kind({{"observer", "robot"}}), InputError);
  EXPECT_THROW(observer_kind({{"observer", 42}}), InputError);
}

}  // namespace
}  // namespace fovlab
