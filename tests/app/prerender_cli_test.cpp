// fovlab prerender: every path-traced frame of a study rendered into stimuli/cache under the working
// directory, what is there kept (a second run renders nothing, a deleted frame alone is rendered
// again, a run killed with SIGKILL resumes with nothing lost), shards that together cover every frame
// once and byte for byte as one run, each frame's .sha256 and --verify, --require-gpu, the
// periphery_bounces pilot's second sequence, and bad input as one line with exit code 2. Tiny studies (32x20, 2 samples, 2 bounces,
// 3 frames) modelled on experiments/fpt_pair.toml.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/digest.h"
#include "core/image_io.h"
#include "core/prng.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;
using fovlab::cli_test::run_in;
using fovlab::cli_test::write_file;

// A fresh working directory per test, its own top-level folder: ctest runs tests in parallel processes.
fs::path working_dir(const std::string& name) {
  return fovlab::cli_test::fresh_folder(fovlab::cli_test::scratch("fovlab-prerender-cli"), name);
}

// A pair study of pt against fpt on the courtyard: 3 frames (0.15 s at 20 frames a second) of 32x20,
// 2 samples a pixel, 2 bounces. `test_extra` and `levels` replace the test's extra keys and levels.
std::string pair_config(const std::string& name,
                        const std::string& levels = "parameter = \"foveal_aperture_deg\"\nvalues = [5, 20]",
                        const std::string& test_extra = "") {
  return "[study]\nname = \"" + name +
         "\"\nseed = 11\n\n"
         "[display]\nwidth_px = 32\nheight_px = 20\nrefresh_hz = 60\ndiagonal_in = 27\nviewing_distance_mm = 500\n\n"
         "[stimulus]\nduration_s = 0.15\nframes_per_second = 20\ncamera_start_s = 2.0\n\n"
         "[stimulus.reference]\nmethod = \"pt\"\nsamples_per_pixel = 2\nmax_bounces = 2\n\n"
         "[stimulus.test]\nmethod = \"fpt\"\nsamples_per_pixel = 2\nmax_bounces = 2\n" +
         test_extra + "\n[levels]\n" + levels +
         "\nhigher_is_better = true\n\n"
         "[protocol]\nkind = \"pair\"\nrepeats = 2\n\n"
         "[timing]\nblack_interval_s = 0.05\ninter_trial_s = 0.05\n\n"
         "[[block]]\nscene = \"courtyard\"\n";
}

fs::path cache_root(const fs::path& dir) { return dir / "stimuli" / "cache"; }

// Cache folders (by name) -> their frame files (by name).
std::map<std::string, std::set<std::string>> cache_contents(const fs::path& dir) {
  std::map<std::string, std::set<std::string>> contents;
  if (!fs::exists(cache_root(dir))) return contents;
  for (const auto& folder : fs::directory_iterator(cache_root(dir))) {
    auto& files = contents[folder.path().filename().string()];
    for (const auto& file : fs::directory_iterator(folder.path())) files.insert(file.path().filename().string());
  }
  return contents;
}

// The files named by the progress lines ("frame i/n ..., ETA ...: FILE"), in order.
std::vector<std::string> rendered_files(const std::string& out) {
  std::vector<std::string> files;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("frame ", 0) != 0) continue;
    const size_t at = line.rfind(": ");
    if (at != std::string::npos) files.push_back(line.substr(at + 2));
  }
  return files;
}

// A frame's pixels.
std::vector<float> pixels(const fs::path& frame) { return fovlab::read_image(frame).pixels; }

const std::set<std::string> kThreeFrames = {"cache.json",         "frame_000000.exr",    "frame_000000.sha256",
                                            "frame_000001.exr",   "frame_000001.sha256", "frame_000002.exr",
                                            "frame_000002.sha256"};

TEST(PrerenderCli, RendersEveryFrameThenNothingOnASecondRun) {
  const fs::path dir = working_dir("all");
  write_file(dir / "study.toml", pair_config("tiny_fpt_pair"));
  const CommandResult first = run_in(dir, "prerender study.toml");
  ASSERT_EQ(first.exit_code, 0) << first.out << first.err;
  EXPECT_NE(
      first.out.find("study.toml: 3 frames in all, shard 0/1 holds 3: 0 cached, 3 to render (cache stimuli/cache)"),
      std::string::npos)
      << first.out;
  EXPECT_NE(first.out.find("rendered 3 frames in "), std::string::npos) << first.out;
  const auto contents = cache_contents(dir);
  ASSERT_EQ(contents.size(), 1u) << "pt and fpt of the same settings share one sequence";
  EXPECT_EQ(contents.begin()->second, kThreeFrames);
  // The progress lines name each frame once, relative to the working directory.
  const std::vector<std::string> files = rendered_files(first.out);
  ASSERT_EQ(files.size(), 3u) << first.out;
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(files[size_t(i)],
              "stimuli/cache/" + contents.begin()->first + "/frame_00000" + std::to_string(i) + ".exr");
    EXPECT_TRUE(fs::is_regular_file(dir / files[size_t(i)]));
  }

  std::map<std::string, fs::file_time_type> times;
  for (const auto& file : fs::directory_iterator(cache_root(dir) / contents.begin()->first))
    times[file.path().filename().string()] = fs::last_write_time(file.path());
  const CommandResult second = run_in(dir, "prerender study.toml");
  ASSERT_EQ(second.exit_code, 0) << second.out << second.err;
  EXPECT_NE(second.out.find("3 frames in all, shard 0/1 holds 3: 3 cached, 0 to render"), std::string::npos)
      << second.out;
  EXPECT_EQ(second.out.find("rendered "), std::string::npos) << second.out;
  EXPECT_TRUE(rendered_files(second.out).empty()) << second.out;
  for (const auto& file : fs::directory_iterator(cache_root(dir) / contents.begin()->first))
    EXPECT_EQ(fs::last_write_time(file.path()), times[file.path().filename().string()]) << file.path() << " rewritten";
  EXPECT_EQ(cache_contents(dir), contents);
}

TEST(PrerenderCli, ShardsTogetherRenderEveryFrameExactlyOnce) {
  const fs::path dir = working_dir("shards");
  write_file(dir / "study.toml", pair_config("tiny_fpt_shards"));
  const CommandResult shard0 = run_in(dir, "prerender study.toml --shard 0/2");
  ASSERT_EQ(shard0.exit_code, 0) << shard0.out << shard0.err;
  EXPECT_NE(shard0.out.find("3 frames in all, shard 0/2 holds 2: 0 cached, 2 to render"), std::string::npos)
      << shard0.out;
  auto contents = cache_contents(dir);
  ASSERT_EQ(contents.size(), 1u);
  EXPECT_EQ(contents.begin()->second, (std::set<std::string>{"cache.json", "frame_000000.exr", "frame_000000.sha256",
                                                             "frame_000002.exr", "frame_000002.sha256"}));

  const CommandResult shard1 = run_in(dir, "prerender study.toml --shard 1/2");
  ASSERT_EQ(shard1.exit_code, 0) << shard1.out << shard1.err;
  EXPECT_NE(shard1.out.find("3 frames in all, shard 1/2 holds 1: 0 cached, 1 to render"), std::string::npos)
      << shard1.out;
  contents = cache_contents(dir);
  ASSERT_EQ(contents.size(), 1u);
  EXPECT_EQ(contents.begin()->second, kThreeFrames);

  // Each frame named by exactly one shard.
  std::vector<std::string> all = rendered_files(shard0.out);
  const std::vector<std::string> more = rendered_files(shard1.out);
  all.insert(all.end(), more.begin(), more.end());
  std::sort(all.begin(), all.end());
  ASSERT_EQ(all.size(), 3u) << shard0.out << shard1.out;
  EXPECT_EQ(std::adjacent_find(all.begin(), all.end()), all.end()) << "a frame rendered by both shards";

  const CommandResult whole = run_in(dir, "prerender study.toml");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  EXPECT_NE(whole.out.find("3 cached, 0 to render"), std::string::npos) << whole.out;

  // A shard count above the number of frames: the shards past the end hold nothing.
  const CommandResult empty_shard = run_in(dir, "prerender study.toml --shard 4/5");
  ASSERT_EQ(empty_shard.exit_code, 0) << empty_shard.err;
  EXPECT_NE(empty_shard.out.find("shard 4/5 holds 0: 0 cached, 0 to render"), std::string::npos) << empty_shard.out;
}

TEST(PrerenderCli, ShardsMatchAWholeRunBitForBit) {
  const fs::path sharded = working_dir("bits-sharded");
  const fs::path whole = working_dir("bits-whole");
  write_file(sharded / "study.toml", pair_config("tiny_fpt_bits"));
  write_file(whole / "study.toml", pair_config("tiny_fpt_bits"));
  ASSERT_EQ(run_in(sharded, "prerender study.toml --shard 1/3").exit_code, 0);
  ASSERT_EQ(run_in(sharded, "prerender study.toml --shard 0/3").exit_code, 0);
  ASSERT_EQ(run_in(sharded, "prerender study.toml --shard 2/3").exit_code, 0);
  ASSERT_EQ(run_in(whole, "prerender study.toml").exit_code, 0);
  const auto contents = cache_contents(whole);
  ASSERT_EQ(cache_contents(sharded), contents);
  ASSERT_EQ(contents.size(), 1u);
  const std::string key = contents.begin()->first;
  EXPECT_EQ(read_all(cache_root(sharded) / key / "cache.json"), read_all(cache_root(whole) / key / "cache.json"));
  for (const std::string& name : contents.begin()->second)  // byte for byte: frames, hashes, cache.json
    EXPECT_TRUE(read_all(cache_root(sharded) / key / name) == read_all(cache_root(whole) / key / name)) << name;
}

TEST(PrerenderCli, ADeletedFrameIsRenderedAgainAndNothingElse) {
  const fs::path dir = working_dir("resume");
  write_file(dir / "study.toml", pair_config("tiny_fpt_resume"));
  ASSERT_EQ(run_in(dir, "prerender study.toml").exit_code, 0);
  const auto contents = cache_contents(dir);
  ASSERT_EQ(contents.size(), 1u);
  const fs::path folder = cache_root(dir) / contents.begin()->first;
  const std::vector<float> frame1 = pixels(folder / "frame_000001.exr");
  const auto time0 = fs::last_write_time(folder / "frame_000000.exr");
  const auto time2 = fs::last_write_time(folder / "frame_000002.exr");
  fs::remove(folder / "frame_000001.exr");

  const CommandResult again = run_in(dir, "prerender study.toml");
  ASSERT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_NE(again.out.find("3 frames in all, shard 0/1 holds 3: 2 cached, 1 to render"), std::string::npos)
      << again.out;
  EXPECT_EQ(rendered_files(again.out),
            std::vector<std::string>{"stimuli/cache/" + contents.begin()->first + "/frame_000001.exr"})
      << again.out;
  EXPECT_EQ(cache_contents(dir), contents);
  EXPECT_TRUE(pixels(folder / "frame_000001.exr") == frame1) << "the same frame again";
  EXPECT_EQ(fs::last_write_time(folder / "frame_000000.exr"), time0);
  EXPECT_EQ(fs::last_write_time(folder / "frame_000002.exr"), time2);

  // A frame that is not an EXR (or of another size) does not count as done: rendered again.
  std::ofstream(folder / "frame_000002.exr", std::ios::binary | std::ios::trunc) << "garbage";
  const CommandResult repaired = run_in(dir, "prerender study.toml");
  ASSERT_EQ(repaired.exit_code, 0) << repaired.out << repaired.err;
  EXPECT_NE(repaired.out.find("2 cached, 1 to render"), std::string::npos) << repaired.out;
  EXPECT_NE(read_all(folder / "frame_000002.exr"), "garbage");
  // Nor does one whose header is whole but whose pixels are cut off.
  const std::string whole = read_all(folder / "frame_000000.exr");
  std::ofstream(folder / "frame_000000.exr", std::ios::binary | std::ios::trunc) << whole.substr(0, whole.size() / 2);
  const CommandResult truncated = run_in(dir, "prerender study.toml");
  ASSERT_EQ(truncated.exit_code, 0) << truncated.out << truncated.err;
  EXPECT_NE(truncated.out.find("2 cached, 1 to render"), std::string::npos) << truncated.out;
  EXPECT_EQ(rendered_files(truncated.out),
            std::vector<std::string>{"stimuli/cache/" + contents.begin()->first + "/frame_000000.exr"})
      << truncated.out;
  EXPECT_EQ(fovlab::read_image(folder / "frame_000000.exr").width, 32);
  EXPECT_NE(run_in(dir, "prerender study.toml").out.find("3 cached, 0 to render"), std::string::npos);
}

// `fovlab prerender study.toml` started in `dir` without waiting; its output is dropped.
pid_t start_prerender(const fs::path& dir) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (chdir(dir.c_str()) != 0) _exit(126);
    freopen("/dev/null", "w", stdout);
    freopen("/dev/null", "w", stderr);
    execl(FOVLAB_BINARY, FOVLAB_BINARY, "prerender", "study.toml", static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

size_t frame_files(const fs::path& dir) {
  size_t frames = 0;
  std::error_code ignored;
  if (!fs::is_directory(cache_root(dir), ignored)) return 0;
  for (const auto& folder : fs::directory_iterator(cache_root(dir)))
    for (const auto& file : fs::directory_iterator(folder.path()))
      frames += file.path().extension() == ".exr" && file.path().filename().string().rfind("frame_", 0) == 0;
  return frames;
}

// The resume promise with real crashes: prerender is killed with SIGKILL, first as soon as its first
// frame is on disk (so the kill lands mid-run), then after random delays up to an uninterrupted
// run's length, and run once more to the end. (Skipped where frames render too fast to land a kill
// between them: a fast GPU.) Every frame ends up on disk exactly as an uninterrupted run renders it, the frames finished
// before a kill are kept as they are, and a killed write leaves at most its hidden temporary
// (".frame_NNNNNN.tmp-<pid>.exr"), never a frame.
TEST(PrerenderCli, KilledRunsResumeWithNothingLost) {
  // Six frames of 32x20 at 128 samples: long enough a run for kills to land between frames.
  const auto config = [](const std::string& name) {
    std::string text = pair_config(name);
    for (const auto& [from, to] : {std::pair<std::string, std::string>{"duration_s = 0.15", "duration_s = 0.3"},
                                   {"samples_per_pixel = 2", "samples_per_pixel = 128"}})
      for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
        text.replace(at, from.size(), to);
    return text;
  };
  const fs::path whole = working_dir("kill-whole");
  const fs::path killed = working_dir("kill-killed");
  write_file(whole / "study.toml", config("tiny_fpt_kill"));
  write_file(killed / "study.toml", config("tiny_fpt_kill"));
  constexpr size_t kFrames = 6;
  // The uninterrupted run, watched: how long it takes, and how long from its first frame to its end.
  const auto started = std::chrono::steady_clock::now();
  const pid_t whole_pid = start_prerender(whole);
  ASSERT_GT(whole_pid, 0);
  std::optional<std::chrono::steady_clock::time_point> first_frame;
  int whole_status = 0;
  while (waitpid(whole_pid, &whole_status, WNOHANG) != whole_pid) {
    if (!first_frame && frame_files(whole) > 0) first_frame = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const auto ended = std::chrono::steady_clock::now();
  ASSERT_TRUE(WIFEXITED(whole_status) && WEXITSTATUS(whole_status) == 0);
  ASSERT_EQ(frame_files(whole), kFrames);
  const double run_s = std::chrono::duration<double>(ended - started).count();
  if (!first_frame || std::chrono::duration<double>(ended - *first_frame).count() < 0.1)
    GTEST_SKIP() << "frames render too fast on this device to kill a run between them";

  // Kill 0 as soon as a frame is on disk; kills 1 to 5 after random delays (a run may finish first).
  fovlab::Pcg32 random(2026);
  std::map<std::string, fs::file_time_type> done_at_first_kill;
  for (int attempt = 0; attempt < 6; ++attempt) {
    const pid_t pid = start_prerender(killed);
    ASSERT_GT(pid, 0);
    const auto attempt_started = std::chrono::steady_clock::now();
    const double delay_s = attempt == 0 ? 10.0 * run_s : run_s * (0.2 + 0.8 * random.uniform());
    int status = 0;
    bool exited = false;
    while (!(exited = waitpid(pid, &status, WNOHANG) == pid)) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - attempt_started).count();
      if (elapsed >= delay_s || (attempt == 0 && frame_files(killed) > 0)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (exited) {
      ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "attempt " << attempt;
      ASSERT_GT(attempt, 0) << "the run finished before its first frame was seen";
      break;
    }
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    if (attempt == 0) {
      ASSERT_LT(frame_files(killed), kFrames) << "the first kill came after the last frame";
      for (const auto& folder : fs::directory_iterator(cache_root(killed)))
        for (const auto& file : fs::directory_iterator(folder.path()))
          if (file.path().filename().string().rfind("frame_", 0) == 0)
            done_at_first_kill[file.path().filename().string()] = fs::last_write_time(file.path());
    }
  }
  ASSERT_FALSE(done_at_first_kill.empty());

  const CommandResult after = run_in(killed, "prerender study.toml");  // finishes what is left
  ASSERT_EQ(after.exit_code, 0) << after.err;
  const auto contents = cache_contents(whole);
  ASSERT_EQ(contents.size(), 1u);
  const std::string key = contents.begin()->first;
  for (const auto& file : fs::directory_iterator(cache_root(killed) / key)) {
    const std::string name = file.path().filename().string();
    if (name[0] == '.') {
      EXPECT_NE(name.find(".tmp-"), std::string::npos) << name;  // a killed write's temporary
      continue;
    }
    ASSERT_TRUE(contents.begin()->second.count(name)) << name;
    EXPECT_TRUE(read_all(file.path()) == read_all(cache_root(whole) / key / name)) << name;
  }
  EXPECT_EQ(frame_files(killed), kFrames);
  for (const auto& [name, time] : done_at_first_kill)  // what was done before the kill is kept, not redone
    EXPECT_EQ(fs::last_write_time(cache_root(killed) / key / name), time) << name;
}

TEST(PrerenderCli, PeripheryBouncesAddASecondSequence) {
  const fs::path dir = working_dir("bounces");
  // Like experiments/fpt_pilot_bounces.toml: periphery_bounces 1 (its own sequence) and 2 (the
  // same as max_bounces: no other sequence) at a fixed fovea.
  write_file(dir / "study.toml", pair_config("tiny_fpt_bounces", "parameter = \"periphery_bounces\"\nvalues = [1, 2]",
                                             "foveal_aperture_deg = 15\n"));
  const CommandResult result = run_in(dir, "prerender study.toml");
  ASSERT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_NE(result.out.find("6 frames in all, shard 0/1 holds 6: 0 cached, 6 to render"), std::string::npos)
      << result.out;
  const auto contents = cache_contents(dir);
  ASSERT_EQ(contents.size(), 2u);
  std::set<std::string> descriptions;
  for (const auto& [key, files] : contents) {
    EXPECT_EQ(files, kThreeFrames) << key;
    descriptions.insert(read_all(cache_root(dir) / key / "cache.json"));
  }
  ASSERT_EQ(descriptions.size(), 2u);
  bool one_bounce = false, two_bounces = false;
  for (const std::string& text : descriptions) {
    one_bounce |= text.find("max_bounces=1;") != std::string::npos;
    two_bounces |= text.find("max_bounces=2;") != std::string::npos;
  }
  EXPECT_TRUE(one_bounce && two_bounces) << *descriptions.begin() << *descriptions.rbegin();
  EXPECT_NE(run_in(dir, "prerender study.toml").out.find("6 cached, 0 to render"), std::string::npos);
}

// Every frame's .sha256 is what --verify (the merge job of fovlab slurm prerender) checks: a frame
// missing, altered after it was rendered, or without its hash is listed, one line each, with exit
// code 1; a second prerender renders the unhashed frame again (nothing says it is the one rendered),
// and the altered and missing ones, and --verify then passes.
TEST(PrerenderCli, VerifyListsFramesThatAreNotWholeAndARerunRepairsThem) {
  const fs::path dir = working_dir("verify");
  write_file(dir / "study.toml", pair_config("tiny_fpt_verify"));
  ASSERT_EQ(run_in(dir, "prerender study.toml").exit_code, 0);
  const auto contents = cache_contents(dir);
  ASSERT_EQ(contents.size(), 1u);
  const fs::path folder = cache_root(dir) / contents.begin()->first;
  for (int frame = 0; frame < 3; ++frame) {
    const std::string name = "frame_00000" + std::to_string(frame);
    EXPECT_EQ(read_all(folder / (name + ".sha256")),
              fovlab::sha256_hex(read_all(folder / (name + ".exr"))) + "  " + name + ".exr\n");
  }
  const CommandResult clean = run_in(dir, "prerender study.toml --verify");
  EXPECT_EQ(clean.exit_code, 0) << clean.out << clean.err;
  EXPECT_NE(
      clean.out.find("3 frames in all, shard 0/1 holds 3 in 1 sequences: 3 whole and matching their .sha256, 0 not"),
      std::string::npos)
      << clean.out;
  const std::string frame1 = read_all(folder / "frame_000001.exr");

  fovlab::Image other(32, 20, 3);  // a whole EXR of the right size, but not the rendered one
  fovlab::write_image(folder / "frame_000000.exr", other);
  fs::remove(folder / "frame_000001.sha256");
  fs::remove(folder / "frame_000002.exr");
  const CommandResult broken = run_in(dir, "prerender study.toml --verify");
  EXPECT_EQ(broken.exit_code, 1) << broken.err;
  const std::string prefix = "stimuli/cache/" + contents.begin()->first + "/";
  for (const std::string& line : std::vector<std::string>{
           prefix + "frame_000000.exr: its bytes differ from its .sha256\n",
           prefix + "frame_000001.exr: no .sha256 beside it\n", prefix + "frame_000002.exr: missing\n",
           std::string("0 whole and matching their .sha256, 3 not")})
    EXPECT_NE(broken.out.find(line), std::string::npos) << line << "\n" << broken.out;
  EXPECT_FALSE(fs::exists(folder / "frame_000002.exr")) << "--verify renders nothing";

  const CommandResult repaired = run_in(dir, "prerender study.toml");
  ASSERT_EQ(repaired.exit_code, 0) << repaired.out << repaired.err;
  EXPECT_NE(
      repaired.out.find("1 frames had no .sha256 beside them (left so by an older fovlab, or replaced and their hash "
                        "deleted): rendered again"),
      std::string::npos)
      << repaired.out;
  EXPECT_NE(repaired.out.find("1 frames differ from their .sha256: rendered again"), std::string::npos) << repaired.out;
  EXPECT_EQ(rendered_files(repaired.out).size(), 3u) << "the unhashed frame is rendered again, not hashed as it is\n"
                                                     << repaired.out;
  EXPECT_EQ(read_all(folder / "frame_000001.exr"), frame1) << "the same frame, rendered again";
  EXPECT_EQ(run_in(dir, "prerender study.toml --verify").exit_code, 0);
  EXPECT_EQ(cache_contents(dir), contents);

  // --verify of one shard checks that shard's frames only.
  fs::remove(folder / "frame_000001.exr");
  EXPECT_EQ(run_in(dir, "prerender study.toml --verify --shard 0/2").exit_code, 0);
  EXPECT_EQ(run_in(dir, "prerender study.toml --verify --shard 1/2").exit_code, 1);
}

// --require-gpu (what fovlab slurm's tasks run with unless --allow-lavapipe) refuses a CPU device.
TEST(PrerenderCli, RequireGpuRefusesLavapipe) {
  const fs::path dir = working_dir("require-gpu");
  write_file(dir / "study.toml", pair_config("tiny_fpt_require_gpu"));
  const CommandResult refused = run_in(dir, "prerender study.toml --device llvmpipe --require-gpu");
  expect_one_line_error(refused, "--require-gpu");
  EXPECT_NE(refused.err.find("renders on the CPU"), std::string::npos) << refused.err;
  EXPECT_EQ(frame_files(dir), 0u);
}

TEST(PrerenderCli, BadShardIsOneLineNamingTheFlag) {
  const fs::path dir = working_dir("bad-shard");
  write_file(dir / "study.toml", pair_config("tiny_fpt_bad_shard"));
  for (const std::string shard : {"2/2", "a/b", "3/2", "1/0", "0.5/2", "1", "1/2/3", ""}) {
    SCOPED_TRACE(shard);
    expect_one_line_error(run_in(dir, "prerender study.toml --shard '" + shard + "'"), "--shard");
  }
  expect_one_line_error(run_in(dir, "prerender study.toml --shard=-1/3"), "--shard");
  expect_one_line_error(run_in(dir, "prerender study.toml --shard -1/3"), "--shard");
  EXPECT_FALSE(fs::exists(dir / "stimuli")) << "bad input rendered something";
}

TEST(PrerenderCli, ConfigsWithoutPathTracedStimuliAreRefused) {
  const fs::path dir = working_dir("sphere");
  // Sphere-traced stimuli only: nothing to pre-render.
  std::string sphere = pair_config("tiny_sphere");
  const auto replace = [](std::string& text, const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace(sphere, "method = \"pt\"\nsamples_per_pixel = 2\nmax_bounces = 2", "method = \"gt\"");
  replace(sphere, "method = \"fpt\"\nsamples_per_pixel = 2\nmax_bounces = 2", "method = \"ipr\"");
  replace(sphere, "parameter = \"foveal_aperture_deg\"\nvalues = [5, 20]",
          "parameter = \"max_steps\"\nvalues = [2, 8]");
  replace(sphere, "scene = \"courtyard\"", "scene = \"primitives\"");
  write_file(dir / "sphere.toml", sphere);
  const CommandResult result = run_in(dir, "prerender sphere.toml");
  expect_one_line_error(result, "sphere.toml");
  EXPECT_NE(result.err.find("no path-traced stimuli"), std::string::npos) << result.err;

  expect_one_line_error(run_in(dir, "prerender missing.toml"), "missing.toml");
  // A pt study on a sphere-traced scene is refused by the config, naming the scene.
  std::string wrong_scene = pair_config("tiny_wrong_scene");
  replace(wrong_scene, "scene = \"courtyard\"", "scene = \"primitives\"");
  write_file(dir / "wrong_scene.toml", wrong_scene);
  expect_one_line_error(run_in(dir, "prerender wrong_scene.toml"), "primitives");
  EXPECT_FALSE(fs::exists(dir / "stimuli")) << "bad input rendered something";
}

}  // namespace
