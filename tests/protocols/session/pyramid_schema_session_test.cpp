// Log schema 10 made the conservative pyramid IPR's default (coarse_test cone, min_filter_size 1:
// thin geometry kept, docs/log-schema.md "Versions"). A session of today's IPR defaults records the
// cone and replays to its hashes; relabelled schema 9, its config reads as the paper's pyramid (ray,
// 3x3), which those sessions showed, so replay names coarse_test and finds other frames; a session
// that showed schema 9's pyramid replays to its hashes as schema 9. On `wires` (64x36), where the
// two pyramids give other frames.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "study/log/event_log.h"
#include "study/log/session_record.h"
#include "tests/protocols/session/session_test_support.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using test::fresh_folder;
using test::read_file;
using test::relabelled_schema;
using test::replay;
using test::simulated;

// 2AFC, GT against IPR at two step caps, one repeat: the test stimulus's lines go after `method`.
std::string ipr_study(const std::string& test_lines) {
  return R"([study]
name = "ipr_schema"
seed = 3

[display]
width_px = 64
height_px = 36
refresh_hz = 60
width_mm = 600
height_mm = 337.5
viewing_distance_mm = 500

[stimulus]
duration_s = 0.05
frames_per_second = 20
camera_start_s = 0

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "ipr"
)" + test_lines +
         R"(
[levels]
parameter = "max_steps"
values = [64, 256]

[protocol]
kind = "2afc"
question = "same"
repeats = 1

[timing]
black_interval_s = 0.05
inter_trial_s = 0.05

[[block]]
scene = "wires"
)";
}

int frame_hash_differences(const ReplayOutcome& replayed) {
  int count = 0;
  for (const std::string& difference : replayed.differences)
    count += difference.find("frame hash") != std::string::npos;
  return count;
}

// The first difference replay names for a stimulus parameter (replay names a stimulus's first, in key order).
std::string first_stimulus_difference(const ReplayOutcome& replayed) {
  for (const std::string& difference : replayed.differences)
    if (difference.find("header: stimulus") == 0) return difference;
  return "";
}

struct RunSession {
  std::string log_path;
  nlohmann::json test_parameters;  // the header's IPR stimulus parameters
};

RunSession run(const std::string& name, const std::string& test_lines) {
  const fs::path results = fresh_folder(name);
  const StudyConfig config = parse_study_config_text(
      ipr_study(test_lines), (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies/ipr_schema.toml").string(),
      renderer_scene_catalog());
  const SessionOutcome outcome = run_session(config, simulated(results));
  EXPECT_TRUE(outcome.finished);
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  RunSession session{outcome.log_path, nullptr};
  for (const nlohmann::json& stimulus : record.header.at("stimuli"))
    if (stimulus.value("method", "") == "ipr") session.test_parameters = stimulus.at("parameters");
  return session;
}

std::string relabelled(const std::string& log_path, int schema) {
  const fs::path path = fs::path(log_path).parent_path() / ("schema" + std::to_string(schema) + ".jsonl");
  std::ofstream(path, std::ios::binary) << relabelled_schema(read_file(log_path), schema);
  return path.string();
}

using PyramidSchemaSession = test::VulkanTest;

TEST_F(PyramidSchemaSession, ASchema10LogReplaysWithTheConeAndASchema9LogWithTheRay) {
  ASSERT_GE(log_schema_version, 10);
  // Today's defaults: the cone without the min filter, recorded in the header, replayed to its hashes.
  const RunSession today = run("ipr-schema-today", "");
  ASSERT_TRUE(today.test_parameters.is_object());
  EXPECT_EQ(today.test_parameters.value("coarse_test", ""), "cone");
  EXPECT_EQ(today.test_parameters.value("min_filter_size", 0), 1);
  const ReplayOutcome replayed = replay(today.log_path);
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());

  // The same log as schema 9 wrote it: its config reads as the paper's pyramid, which is not what it showed.
  const ReplayOutcome as_nine = replay(relabelled(today.log_path, 9));
  EXPECT_NE(first_stimulus_difference(as_nine).find("parameters.coarse_test: none by this build's reading"),
            std::string::npos)
      << first_stimulus_difference(as_nine);
  EXPECT_GT(frame_hash_differences(as_nine), 0) << "the cone's frames are not the ray's on wires";

  // A session that showed schema 9's pyramid (named), as schema 9: its frames replay to their hashes.
  const RunSession paper = run("ipr-schema-nine", "coarse_test = \"ray\"\nmin_filter_size = 3\n");
  EXPECT_FALSE(paper.test_parameters.contains("coarse_test")) << "ray, the earlier default, is left out";
  EXPECT_EQ(paper.test_parameters.value("min_filter_size", 0), 3);
  const ReplayOutcome paper_as_nine = replay(relabelled(paper.log_path, 9));
  EXPECT_GT(paper_as_nine.difference_count, 0) << "the chain no longer holds";
  EXPECT_EQ(first_stimulus_difference(paper_as_nine), "");
  EXPECT_EQ(frame_hash_differences(paper_as_nine), 0);
}

}  // namespace
}  // namespace fovlab
