// A sampling model's `equalise` in sessions and replay across log schema 8: "on" meant the
// theoretical density before it and means equal shaded samples since (foveation/sampling_map.h
// Equalise; render_method.h ParameterDescriptor::choice_alias). A log of an earlier schema whose
// config says "on" replays to its hashes with the density solve, keeping the stimuli it recorded.
// Small (64x48), short, on the primitives scene, so it runs in seconds on lavapipe.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "study/log/event_log.h"
#include "tests/protocols/session/session_test_support.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using test::fresh_folder;
using test::read_file;
using test::relabelled_schema;
using test::replay;

// 2AFC, GT against the hyperbolic model over sigma, its zones small enough for this display.
const std::string kStudy = R"([study]
name = "equalise_session"
seed = 9

[display]
width_px = 64
height_px = 48
refresh_hz = 60
width_mm = 240
height_mm = 180
viewing_distance_mm = 300

[stimulus]
duration_s = 0.05
frames_per_second = 20
camera_start_s = 0.5

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "hyperbolic"
inner_radius_deg = 3
outer_radius_deg = 6
blend_band_deg = 0.5
EQUALISE

[levels]
parameter = "sigma"
values = [2.2, 2.6]

[protocol]
kind = "2afc"
question = "same"
repeats = 1

[timing]
black_interval_s = 0.05
inter_trial_s = 0.05

[[block]]
scene = "primitives"
)";

std::string study_text(const std::string& equalise_line) {
  std::string text = kStudy;
  text.replace(text.find("EQUALISE"), 8, equalise_line);
  return text;
}

SessionOptions simulated(const fs::path& results) {
  const fs::path trace = results / "still.csv";
  fs::create_directories(results);
  std::ofstream(trace) << "time_s,x_px,y_px\n0,20.5,30.25\n";
  return test::simulated_on_trace(results, trace);
}

int differences_containing(const ReplayOutcome& replayed, const std::string& text) {
  int count = 0;
  for (const std::string& difference : replayed.differences) count += difference.find(text) != std::string::npos;
  return count;
}

// `text` with every `from` replaced by `to`; at least one must be there.
std::string replaced_all(std::string text, const std::string& from, const std::string& to) {
  size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  for (; at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
  return text;
}

// What a build before schema 8 wrote for a session of `equalise = "on"`: the config's "on", the
// stimuli's "on", and its schema. Made from a session of today's "density" (what "on" meant), so the
// frames are those an earlier build showed; the edit breaks the chain, which replay also says.
std::string as_schema(const std::string& log_text, int schema) {
  std::string text = replaced_all(log_text, "equalise = \\\"density\\\"", "equalise = \\\"on\\\"");
  text = replaced_all(text, "\"equalise\":\"density\"", "\"equalise\":\"on\"");
  return relabelled_schema(text, schema);
}

TEST(SamplingEqualiseSession, ALogBeforeSchema8ReadsOnAsTheDensity) {
  ASSERT_GE(log_schema_version, 8);
  const fs::path results = fresh_folder("equalise-density");
  const SessionOutcome outcome =
      run_session(parse_study_config_text(study_text("equalise = \"density\""), "equalise.toml", renderer_scene_catalog()),
                  simulated(results));
  ASSERT_TRUE(outcome.finished);
  EXPECT_EQ(replay(outcome.log_path).difference_count, 0);
  const std::string text = read_file(outcome.log_path);

  // As schema 7 wrote it: the frames and the stimuli are those it recorded.
  const fs::path earlier = results / "schema7.jsonl";
  std::ofstream(earlier, std::ios::binary) << as_schema(text, 7);
  const ReplayOutcome old = replay(earlier.string());
  EXPECT_GT(old.difference_count, 0) << "the chain no longer holds";
  EXPECT_EQ(differences_containing(old, "frame hash"), 0);
  EXPECT_EQ(differences_containing(old, "header: stimul"), 0) << (old.differences.empty() ? "" : old.differences[0]);

  // The same log claiming schema 8: "on" is read as samples, which is neither the stimuli nor the
  // frames it records.
  const fs::path today = results / "schema8.jsonl";
  std::ofstream(today, std::ios::binary) << as_schema(text, 8);
  const ReplayOutcome anew = replay(today.string());
  EXPECT_GT(differences_containing(anew, "\"samples\" by this build's reading of config_toml"), 0)
      << (anew.differences.empty() ? "" : anew.differences[0]);
  EXPECT_GT(differences_containing(anew, "frame hash"), 0) << "equal samples solve another s3 than the density";
}

// Today's "on" is "samples": the header records "samples" and the session replays.
TEST(SamplingEqualiseSession, OnNowRecordsSamplesAndReplays) {
  const fs::path results = fresh_folder("equalise-on");
  const SessionOutcome outcome =
      run_session(parse_study_config_text(study_text("equalise = \"on\""), "equalise.toml", renderer_scene_catalog()),
                  simulated(results));
  ASSERT_TRUE(outcome.finished);
  const std::string text = read_file(outcome.log_path);
  EXPECT_NE(text.find("\"equalise\":\"samples\""), std::string::npos);
  EXPECT_EQ(text.find("\"equalise\":\"on\""), std::string::npos);
  EXPECT_EQ(replay(outcome.log_path).difference_count, 0);
}

}  // namespace
}  // namespace fovlab
