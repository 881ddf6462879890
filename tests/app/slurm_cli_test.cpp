// fovlab slurm on a real Slurm: scripts/local-slurm starts a private munged, slurmctld and slurmd
// (one node, loopback, everything under the test's folder); `fovlab slurm prerender --submit` runs a
// 4-task array over a small path-traced study, one task's fovlab is killed with SIGKILL mid-way, the
// task requeues itself and resumes from the cache, the merge job verifies every frame against its
// .sha256, and the cache is byte for byte the one a single-machine `fovlab prerender` writes. A
// sharded `fovlab slurm bench` sweep merges into the report one run writes. Skipped, with the
// script's reason, where the daemons cannot run (not root, Slurm or munge not installed). Also: the
// scripts as written, and bad flags as one line with exit code 2, without a cluster.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;
using fovlab::cli_test::run;
using fovlab::cli_test::write_file;

fs::path working_dir(const std::string& name) {
  const fs::path dir = fovlab::cli_test::scratch("fovlab-slurm-cli") / name;
  // A cluster an earlier run left behind (killed by ctest's timeout) is stopped before its folder goes.
  if (fs::exists(dir / "slurm-daemons" / "run"))
    std::system(("'" + std::string(FOVLAB_SOURCE_DIR) + "/scripts/local-slurm' stop '" +
                 (dir / "slurm-daemons").string() + "' 2>/dev/null")
                    .c_str());
  return fovlab::cli_test::fresh_folder(dir.parent_path(), name);
}

// A pair study of pt against fpt on the courtyard, 32x20: `frames` frames at 20 a second,
// `samples` samples a pixel, 2 bounces (as tests/app/prerender_cli_test.cpp's).
std::string study(const std::string& name, int frames, int samples) {
  const std::string spp = std::to_string(samples);
  std::ostringstream duration;
  duration << frames / 20.0;
  return "[study]\nname = \"" + name +
         "\"\nseed = 11\n\n"
         "[display]\nwidth_px = 32\nheight_px = 20\nrefresh_hz = 60\ndiagonal_in = 27\nviewing_distance_mm = 500\n\n"
         "[stimulus]\nduration_s = " +
         duration.str() +
         "\nframes_per_second = 20\ncamera_start_s = 2.0\n\n"
         "[stimulus.reference]\nmethod = \"pt\"\nsamples_per_pixel = " +
         spp +
         "\nmax_bounces = 2\n\n"
         "[stimulus.test]\nmethod = \"fpt\"\nsamples_per_pixel = " +
         spp +
         "\nmax_bounces = 2\n"
         "\n[levels]\nparameter = \"foveal_aperture_deg\"\nvalues = [5, 20]\nhigher_is_better = true\n\n"
         "[protocol]\nkind = \"pair\"\nrepeats = 2\n\n"
         "[timing]\nblack_interval_s = 0.05\ninter_trial_s = 0.05\n\n"
         "[[block]]\nscene = \"courtyard\"\n";
}

// Runs `command` through bash in `dir` with the cluster's SLURM_CONF (empty: none).
CommandResult shell_in(const fs::path& dir, const std::string& command, const std::string& slurm_conf = "") {
  const fs::path out = dir / ".shell.stdout";
  const fs::path err = dir / ".shell.stderr";
  const std::string line = "cd '" + dir.string() + "' && " +
                           (slurm_conf.empty() ? "" : "SLURM_CONF='" + slurm_conf + "' ") + command + " >'" +
                           out.string() + "' 2>'" + err.string() + "'";
  const int status = std::system(("bash -c \"" + line + "\"").c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_all(out), read_all(err)};
}

// The private cluster of one test: started in its constructor (skipped() says why when it could not
// be), stopped in its destructor whatever the test's outcome.
class LocalSlurm {
 public:
  explicit LocalSlurm(const fs::path& dir) : dir_(dir / "slurm-daemons") {
    const CommandResult started =
        shell_in(dir, "'" + std::string(FOVLAB_SOURCE_DIR) + "/scripts/local-slurm' start '" + dir_.string() + "'");
    if (started.exit_code == 77) {
      skip_reason_ = started.err.empty() ? "scripts/local-slurm: skipped" : started.err;
      return;
    }
    running_ = true;
    EXPECT_EQ(started.exit_code, 0) << started.out << started.err;
    conf_ = (dir_ / "slurm.conf").string();
  }
  ~LocalSlurm() {
    if (running_)
      std::system(
          ("'" + std::string(FOVLAB_SOURCE_DIR) + "/scripts/local-slurm' stop '" + dir_.string() + "'").c_str());
  }
  LocalSlurm(const LocalSlurm&) = delete;
  LocalSlurm& operator=(const LocalSlurm&) = delete;

  const std::string& skip_reason() const { return skip_reason_; }
  const std::string& conf() const { return conf_; }
  const fs::path& dir() const { return dir_; }

  // `scontrol show job ID`'s JobState (COMPLETED, FAILED, PENDING, ...).
  std::string job_state(const fs::path& from, const std::string& id) const {
    const std::string text = shell_in(from, "scontrol show job " + id, conf_).out;
    std::smatch match;
    return std::regex_search(text, match, std::regex("JobState=(\\S+)")) ? match[1].str() : "unknown: " + text;
  }
  // Waits until squeue lists no job; false after `timeout`.
  bool wait_until_idle(const fs::path& from, std::chrono::seconds timeout) const {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
      const CommandResult queue = shell_in(from, "squeue -h", conf_);
      if (queue.exit_code == 0 && queue.out.empty()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
    return false;
  }

 private:
  fs::path dir_;
  std::string conf_;
  std::string skip_reason_;
  bool running_ = false;
};

// "array A merge M" from the folder's submitted.txt.
std::pair<std::string, std::string> submitted_jobs(const fs::path& folder) {
  std::smatch match;
  const std::string text = read_all(folder / "submitted.txt");
  if (!std::regex_search(text, match, std::regex("array (\\d+) merge (\\d+)"))) return {};
  return {match[1].str(), match[2].str()};
}

// The process whose command line holds every one of `words`, if any.
std::optional<pid_t> process_with(const std::vector<std::string>& words) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string line = read_all(entry.path() / "cmdline");
    std::replace(line.begin(), line.end(), '\0', ' ');
    bool all = !line.empty();
    for (const std::string& word : words) all = all && line.find(word) != std::string::npos;
    if (all) return pid_t(std::stol(name));
  }
  return std::nullopt;
}

// Every file under `root` (relative name -> bytes).
std::map<std::string, std::string> files_under(const fs::path& root) {
  std::map<std::string, std::string> files;
  if (!fs::exists(root)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(root))
    if (entry.is_regular_file()) files[fs::relative(entry.path(), root).string()] = read_all(entry.path());
  return files;
}

TEST(SlurmCli, KilledTaskRequeuesAndTheMergedCacheIsOneMachinesByteForByte) {
  const fs::path dir = working_dir("prerender");
  LocalSlurm slurm(dir);
  if (!slurm.skip_reason().empty()) GTEST_SKIP() << slurm.skip_reason();
  ASSERT_FALSE(slurm.conf().empty());
  // 8 frames: task I of 4 renders frames I and I + 4. 384 samples make a frame take about a second
  // with four tasks on two cores, so task 1 is killed while it renders frame 5.
  write_file(dir / "study.toml", study("slurm_prerender", 8, 384));
  const CommandResult written = shell_in(
      dir,
      std::string(FOVLAB_BINARY) + " slurm prerender study.toml --tasks 4 --allow-lavapipe --max-requeue 2 --submit",
      slurm.conf());
  ASSERT_EQ(written.exit_code, 0) << written.out << written.err;
  const fs::path folder = dir / "slurm" / "study-prerender";
  const auto [array, merge] = submitted_jobs(folder);
  ASSERT_FALSE(array.empty()) << written.out << read_all(folder / "submitted.txt");

  // Task 1's first frame on disk: kill its fovlab (it is rendering frame 5).
  const fs::path cache = dir / "stimuli" / "cache";
  std::optional<fs::path> frame1;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(180);
  while (!frame1 && std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(cache))
      for (const auto& sequence : fs::directory_iterator(cache))
        if (fs::exists(sequence.path() / "frame_000001.exr"))
          frame1 = sequence.path() / "frame_000001.exr";  // its hash first
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(frame1) << "task 1 rendered nothing in 180 s: " << read_all(slurm.dir() / "log" / "slurmd.log");
  const auto frame1_time = fs::last_write_time(*frame1);
  const std::optional<pid_t> task1 = process_with({"prerender", (dir / "study.toml").string(), "--shard", "1/4"});
  if (!task1 || kill(*task1, SIGKILL) != 0)
    GTEST_SKIP() << "task 1 finished its second frame before it could be killed (frames render too fast here)";

  ASSERT_TRUE(slurm.wait_until_idle(dir, std::chrono::seconds(300))) << shell_in(dir, "squeue", slurm.conf()).out;
  for (int task = 0; task < 4; ++task)
    EXPECT_EQ(slurm.job_state(dir, array + "_" + std::to_string(task)), "COMPLETED") << "task " << task;
  EXPECT_EQ(slurm.job_state(dir, merge), "COMPLETED");

  // Task 1 ran twice: killed, requeued, and resumed with frame 1 kept as it was.
  const std::string task1_log = read_all(folder / "logs" / ("task-" + array + "_1.log"));
  EXPECT_NE(task1_log.find("attempt 1,"), std::string::npos) << task1_log;
  EXPECT_NE(task1_log.find("exit 137"), std::string::npos) << task1_log;
  EXPECT_NE(task1_log.find("killed; requeued"), std::string::npos) << task1_log;
  EXPECT_NE(task1_log.find("attempt 2,"), std::string::npos) << task1_log;
  // Frame 1 kept; frame 5 rendered again, or (a kill that landed after frame 5 was on disk) kept.
  EXPECT_TRUE(task1_log.find("shard 1/4 holds 2: 1 cached, 1 to render") != std::string::npos ||
              task1_log.find("shard 1/4 holds 2: 2 cached, 0 to render") != std::string::npos)
      << task1_log;
  EXPECT_EQ(fs::last_write_time(*frame1), frame1_time) << "frame 1 was rendered again";
  const std::string merge_log = read_all(folder / "logs" / ("merge-" + merge + ".log"));
  EXPECT_NE(
      merge_log.find("8 frames in all, shard 0/1 holds 8 in 1 sequences: 8 whole and matching their .sha256, 0 not"),
      std::string::npos)
      << merge_log;

  // One machine, the same study: the same files, byte for byte (frames, hashes, cache.json).
  const fs::path single = working_dir("prerender-single");
  write_file(single / "study.toml", study("slurm_prerender", 8, 384));
  const CommandResult whole = shell_in(single, std::string(FOVLAB_BINARY) + " prerender study.toml");
  ASSERT_EQ(whole.exit_code, 0) << whole.out << whole.err;
  const auto expected = files_under(single / "stimuli" / "cache");
  const auto merged = files_under(cache);
  ASSERT_EQ(expected.size(), 17u) << "cache.json and 8 frames with their .sha256";
  std::set<std::string> expected_names, merged_names;
  for (const auto& [name, bytes] : expected) expected_names.insert(name);
  for (const auto& [name, bytes] : merged)
    if (fs::path(name).filename().string()[0] != '.') merged_names.insert(name);  // a killed write's hidden temporary
  EXPECT_EQ(merged_names, expected_names);
  for (const auto& [name, bytes] : expected) {
    const auto found = merged.find(name);
    ASSERT_NE(found, merged.end()) << name;
    EXPECT_TRUE(found->second == bytes) << name << " differs from the single-machine pre-render";
  }
}

TEST(SlurmCli, ShardedBenchSweepMergesIntoOneRunsReport) {
  const fs::path dir = working_dir("bench");
  LocalSlurm slurm(dir);
  if (!slurm.skip_reason().empty()) GTEST_SKIP() << slurm.skip_reason();
  ASSERT_FALSE(slurm.conf().empty());
  const std::string flags = "--scenes primitives,columns --spp 1,4 --width 32 --height 18 --repeats 1";
  const CommandResult written = shell_in(
      dir, std::string(FOVLAB_BINARY) + " slurm bench --tasks 3 --allow-lavapipe " + flags + " --submit", slurm.conf());
  ASSERT_EQ(written.exit_code, 0) << written.out << written.err;
  const fs::path folder = dir / "slurm" / "bench";
  const auto [array, merge] = submitted_jobs(folder);
  ASSERT_FALSE(merge.empty()) << written.out;
  ASSERT_TRUE(slurm.wait_until_idle(dir, std::chrono::seconds(300))) << shell_in(dir, "squeue", slurm.conf()).out;
  ASSERT_EQ(slurm.job_state(dir, merge), "COMPLETED") << read_all(folder / "logs" / ("merge-" + merge + ".log"));

  const CommandResult whole = shell_in(dir, std::string(FOVLAB_BINARY) + " bench " + flags + " --json whole.json");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const nlohmann::json one = nlohmann::json::parse(read_all(dir / "whole.json"));
  const nlohmann::json merged = nlohmann::json::parse(read_all(folder / "bench.json"));
  for (const char* key : {"command", "device", "width", "height", "methods", "metrics"})
    EXPECT_EQ(merged[key], one[key]) << key;
  ASSERT_EQ(merged["rows"].size(), 4u);
  ASSERT_EQ(merged["cells"].size(), one["cells"].size());
  // The same units in the same order, with the same frames: every error is equal (times differ).
  for (size_t i = 0; i < merged["cells"].size(); ++i)
    for (const char* key : {"method", "scene", "spp", "ssim", "psnr_db", "flip"})
      EXPECT_EQ(merged["cells"][i][key], one["cells"][i][key]) << "cell " << i << " " << key;
  for (const char* file : {"table.md", "primitives_pareto_flip.svg", "columns_pareto_ssim.svg", "bench.json"})
    EXPECT_TRUE(fs::is_regular_file(folder / "report" / file)) << file;
}

// Without a cluster: what the scripts say, and bad flags.
TEST(SlurmCli, WritesReadableScriptsAndRefusesBadFlags) {
  const fs::path dir = working_dir("scripts");
  write_file(dir / "study.toml", study("slurm_scripts", 3, 2));
  const CommandResult written = shell_in(
      dir,
      std::string(FOVLAB_BINARY) +
          " slurm prerender study.toml --tasks 3 --partition gpu --gpus-per-task a100:1 --time-limit 2:00:00 --mem 8G");
  ASSERT_EQ(written.exit_code, 0) << written.err;
  const fs::path folder = dir / "slurm" / "study-prerender";
  const std::string array = read_all(folder / "array.sbatch");
  for (const std::string& line : std::vector<std::string>{
           "#SBATCH --array=0-2", "#SBATCH --requeue", "#SBATCH --partition=gpu", "#SBATCH --gpus-per-task=a100:1",
           "#SBATCH --time=2:00:00", "#SBATCH --mem=8G", "#SBATCH --chdir=" + dir.string(),
           "--shard \"${task}/3\" --require-gpu", "scontrol requeue", "-lt 3 ]"})
    EXPECT_NE(array.find(line), std::string::npos) << line << "\n" << array;
  const std::string merge = read_all(folder / "merge.sbatch");
  EXPECT_NE(merge.find("prerender " + (dir / "study.toml").string() + " --cache " +
                       (dir / "stimuli" / "cache").string() + " --verify"),
            std::string::npos)
      << merge;
  EXPECT_EQ(merge.find("#SBATCH --gpus-per-task"), std::string::npos) << "the merge needs no GPU";
  EXPECT_NE(read_all(folder / "submit.sh").find("--dependency=afterok:${array}"), std::string::npos);
  EXPECT_FALSE(fs::exists(folder / "submitted.txt")) << "nothing submitted without --submit";
  for (const char* script : {"array.sbatch", "merge.sbatch", "submit.sh"})
    EXPECT_EQ(shell_in(folder, std::string("bash -n ") + script).exit_code, 0) << script;

  // Bench flags are passed on quoted, and checked as bench checks them.
  const CommandResult bench = shell_in(
      dir, std::string(FOVLAB_BINARY) + " slurm bench --tasks 2 --scenes primitives --spp 1,4 --width 64 --height 36");
  ASSERT_EQ(bench.exit_code, 0) << bench.err;
  const std::string bench_array = read_all(dir / "slurm" / "bench" / "array.sbatch");
  EXPECT_NE(bench_array.find("bench --scenes primitives --spp 1,4 --width 64 --height 36 --cells \"${task}/2\""),
            std::string::npos)
      << bench_array;
  EXPECT_NE(read_all(dir / "slurm" / "bench" / "merge.sbatch").find("/part-{0..1}.json --json"), std::string::npos);
  EXPECT_NE(bench_array.find("#SBATCH --exclusive\n"), std::string::npos) << "a sweep's tasks do not share a node";
  EXPECT_EQ(array.find("--exclusive"), std::string::npos) << "a pre-render's may";

  const std::string fovlab = std::string(FOVLAB_BINARY) + " ";
  const auto refused = [&](const std::string& arguments, const std::string& names) {
    SCOPED_TRACE(arguments);
    expect_one_line_error(shell_in(dir, fovlab + arguments), names);
  };
  refused("slurm prerender study.toml --tasks 4", "--tasks 4: expected 1 to 3");
  refused("slurm prerender study.toml --tasks 0", "--tasks 0");
  refused("slurm prerender study.toml --tasks 2 --partition 'a;rm -rf /'", "--partition");
  refused("slurm prerender study.toml --tasks 2 --time-limit soon", "--time-limit");
  refused("slurm prerender study.toml --tasks 2 --gpus-per-task 0", "--gpus-per-task");
  refused("slurm prerender study.toml --tasks 2 --mem lots", "--mem");
  refused("slurm prerender missing.toml --tasks 2", "missing.toml");
  refused("slurm prerender study.toml --tasks 2 --fovlab /nonexistent/fovlab", "--fovlab");
  refused("slurm bench --tasks 5 --scenes primitives --spp 1,4", "--tasks 5: expected 1 to 2");
  refused("slurm bench --tasks 2 --spp 1 --json x.json", "--json");
  refused("slurm bench --tasks 2 --spp 1 --cells 0/2", "--cells");
  refused("slurm bench --tasks 1 --spp 0", "spp");
  refused("slurm bench --tasks 1 --no-such-flag", "--no-such-flag");
  // --submit where sbatch is not on PATH: one line saying so, scripts kept.
  expect_one_line_error(
      shell_in(dir, "PATH=/nonexistent " + fovlab + "slurm prerender study.toml --tasks 2 --submit --out nopath"),
      "sbatch is not on PATH");
  EXPECT_TRUE(fs::exists(dir / "nopath" / "submit.sh"));
}

}  // namespace
