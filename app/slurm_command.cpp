// fovlab slurm prerender CONFIG --tasks N [...] and fovlab slurm bench --tasks N [...] [bench flags]:
// write, and with --submit submit through sbatch, a Slurm job array whose task I runs
// `fovlab prerender CONFIG --shard I/N` (or `fovlab bench ... --cells I/N --json parts/part-I.json`),
// and a merge job that runs once every task has succeeded (`prerender --verify`; `bench-merge`). The
// scripts are plain bash in one folder, to read and edit: array.sbatch, merge.sbatch, submit.sh
// (docs/scale-out.md).
//
// Faults: the array asks for --requeue, so Slurm requeues a task it pre-empts (PreemptMode=REQUEUE)
// or loses with its node; a task whose fovlab alone dies of a signal (the OOM killer, a kill of the
// process) requeues itself with scontrol, up to --max-requeue times. Either way the task resumes from
// the cache (frames are written atomically, each with its .sha256). A task that fails on bad input
// (exit 2) or otherwise, or runs out of its time limit, stays failed, and the merge job is then
// cancelled (afterok, --kill-on-invalid-dep). Tasks refuse a CPU Vulkan device (--require-gpu)
// unless --allow-lavapipe.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "app/bench_flags.h"
#include "app/cli_support.h"
#include "app/commands.h"
#include "app/output_options.h"
#include "app/prerender_jobs.h"
#include "core/atomic_file.h"
#include "core/input_error.h"
#include "core/input_file.h"

namespace fovlab::app {

namespace {

namespace fs = std::filesystem;

// The flags both kinds of job take.
struct SlurmOptions {
  int tasks = 0;
  std::string partition;
  std::string account;
  std::string gpus_per_task;
  std::string time_limit;
  std::string mem;
  int cpus_per_task = 1;
  int max_requeue = 3;
  bool allow_lavapipe = false;
  bool share_nodes = false;  // bench: let tasks share a node (their times then disturb each other)
  bool submit = false;
  std::string out;     // the scripts' folder; default slurm/<name>
  std::string fovlab;  // the binary the tasks run; default this one
};

// One word for bash: as it is when it holds only safe characters, single-quoted otherwise.
std::string shell_word(const std::string& text) {
  if (std::regex_match(text, std::regex("[A-Za-z0-9_./,:=+@%-]+"))) return text;
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

void check_pattern(const std::string& flag, const std::string& value, const char* pattern,
                   const std::string& expected) {
  if (!value.empty() && !std::regex_match(value, std::regex(pattern))) fail_flag(flag, expected, value);
}

void check_slurm_flags(const SlurmOptions& options, int work_items, const std::string& what) {
  if (options.tasks < 1 || options.tasks > work_items)
    throw InputError("--tasks " + std::to_string(options.tasks) + ": expected 1 to " + std::to_string(work_items) +
                     " (the " + what + ": a task more would have nothing to do)");
  check_pattern("--partition", options.partition, "[A-Za-z0-9_.,-]+", "a partition name (letters, digits, _ . , -)");
  check_pattern("--account", options.account, "[A-Za-z0-9_.-]+", "an account name (letters, digits, _ . -)");
  check_pattern("--gpus-per-task", options.gpus_per_task, "([A-Za-z0-9_.-]+:)?[1-9][0-9]*",
                "a count of GPUs, optionally with a type (1, a100:2)");
  check_pattern("--time-limit", options.time_limit, "([0-9]+-)?[0-9]+(:[0-9]+){0,2}",
                "Slurm's time limit: minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM or D-HH:MM:SS");
  check_pattern("--mem", options.mem, "[1-9][0-9]*[KMGT]?", "memory per node with an optional unit (16G, 4000M)");
  if (options.cpus_per_task < 1 || options.cpus_per_task > 4096)
    throw InputError("--cpus-per-task " + std::to_string(options.cpus_per_task) + ": expected 1 to 4096");
  if (options.max_requeue < 0 || options.max_requeue > 100)
    throw InputError("--max-requeue " + std::to_string(options.max_requeue) + ": expected 0 to 100");
}

// A word that goes into a script: no control character (a newline would end a comment or an #SBATCH
// line and start a command).
void check_script_word(const std::string& what, const std::string& word) {
  for (unsigned char c : word)
    if (c < 0x20 || c == 0x7f)
      throw InputError(what + ": holds a control character (code " + std::to_string(int(c)) +
                       "); expected text that fits on one line of a script");
}

// A path written into an #SBATCH line, where sbatch takes no quoting and --output expands %.
void check_sbatch_path(const std::string& what, const std::string& path) {
  check_script_word(what, path);
  if (path.find_first_of(" \t%\"'\\") != std::string::npos)
    throw InputError(what + " " + path +
                     ": holds a space, quote, backslash or %, which an #SBATCH line cannot; "
                     "expected a path without them (run from another folder, or give --out)");
}

std::string absolute_text(const std::string& path) { return fs::absolute(path).lexically_normal().string(); }

// The binary the tasks run: --fovlab, or this one.
std::string fovlab_binary(const SlurmOptions& options) {
  if (!options.fovlab.empty()) {
    std::error_code error;
    if (!fs::is_regular_file(options.fovlab, error))
      fail_flag("--fovlab", "the fovlab binary the tasks run (a file)", options.fovlab);
    return absolute_text(options.fovlab);
  }
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) throw InputError("--fovlab: this binary's path is unknown (/proc/self/exe); expected --fovlab PATH");
  return self.string();
}

// What differs between the two kinds of job.
struct Job {
  std::string kind;           // "prerender" or "bench"
  std::string what;           // one line: what task I does
  std::string task_command;   // bash, "${task}" is the task's index
  std::string merge_command;  // bash
  std::string merge_what;     // one line: what the merge job does
  bool exclusive = false;     // each task a node of its own (#SBATCH --exclusive)
};

std::string sbatch_lines(const SlurmOptions& options, bool gpus) {
  std::string lines;
  const auto line = [&](const std::string& flag, const std::string& value) {
    if (!value.empty()) lines += "#SBATCH --" + flag + "=" + value + "\n";
  };
  line("partition", options.partition);
  line("account", options.account);
  line("time", options.time_limit);
  line("mem", options.mem);
  if (gpus) line("gpus-per-task", options.gpus_per_task);
  return lines;
}

void write_job(const SlurmOptions& options, const std::string& invocation, const Job& job, const fs::path& out) {
  const std::string working_dir = fs::current_path().string();
  check_sbatch_path("the working directory", working_dir);
  check_sbatch_path("--out", out.string());
  check_script_word("the command line", invocation);
  const std::string tasks = std::to_string(options.tasks);
  const std::string requeues = std::to_string(options.max_requeue);
  const std::string logs = (out / "logs").string();
  std::string array =
      "#!/bin/bash\n"
      "# fovlab slurm " +
      job.kind + ": task I of " + tasks + " (I = SLURM_ARRAY_TASK_ID) " + job.what +
      "\n"
      "# Written by: " +
      invocation +
      "\n"
      "# Edit freely; submit.sh submits it, then merge.sbatch after every task has succeeded.\n"
      "#SBATCH --job-name=fovlab-" +
      job.kind +
      "\n"
      "#SBATCH --array=0-" +
      std::to_string(options.tasks - 1) +
      "\n"
      "#SBATCH --chdir=" +
      working_dir +
      "\n"
      "#SBATCH --output=" +
      logs +
      "/task-%A_%a.log\n"
      "#SBATCH --open-mode=append\n"
      "#SBATCH --requeue\n"
      "#SBATCH --cpus-per-task=" +
      std::to_string(options.cpus_per_task) + "\n" + (job.exclusive ? "#SBATCH --exclusive\n" : "") +
      sbatch_lines(options, true) +
      "set -u\n"
      "task=${SLURM_ARRAY_TASK_ID}\n"
      "restarts=${SLURM_RESTART_COUNT:-0}\n"
      "echo \"fovlab slurm: task ${task} of " +
      tasks +
      ", attempt $((restarts + 1)), job ${SLURM_JOB_ID} on "
      "$(hostname) at $(date -u +%Y-%m-%dT%H:%M:%SZ)\"\n" +
      job.task_command +
      "\n"
      "status=$?\n"
      "echo \"fovlab slurm: task ${task} exit ${status}\"\n"
      "# fovlab killed by a signal (exit 128 + its number: the OOM killer, a kill of the process): requeue\n"
      "# this task, at most " +
      requeues +
      " times; it resumes from what is already done. Pre-emption and\n"
      "# node failures are requeued by Slurm itself (--requeue above). Bad input (exit 2) and other\n"
      "# failures (1) stay failed, and the merge job is then cancelled.\n"
      "if [ \"${status}\" -gt 128 ] && [ \"${restarts}\" -lt " +
      requeues +
      " ]; then\n"
      "  echo \"fovlab slurm: task ${task} killed; requeued\"\n"
      "  scontrol requeue \"${SLURM_JOB_ID}\"\n"
      "fi\n"
      "exit \"${status}\"\n";
  std::string merge =
      "#!/bin/bash\n"
      "# fovlab slurm " +
      job.kind + ": " + job.merge_what +
      "\n"
      "# Written by: " +
      invocation +
      "\n"
      "#SBATCH --job-name=fovlab-" +
      job.kind +
      "-merge\n"
      "#SBATCH --chdir=" +
      working_dir +
      "\n"
      "#SBATCH --output=" +
      logs +
      "/merge-%j.log\n"
      "#SBATCH --cpus-per-task=1\n" +
      sbatch_lines(options, false) + "set -u\n" + job.merge_command + "\n";
  std::string submit =
      "#!/bin/bash\n"
      "# Submits array.sbatch (" +
      tasks +
      " tasks), then merge.sbatch to run once every task has succeeded\n"
      "# (afterok; cancelled if a task fails for good). Job IDs are appended to submitted.txt.\n"
      "set -euo pipefail\n"
      "cd \"$(dirname \"$0\")\"\n"
      "mkdir -p logs\n"
      "array=$(sbatch --parsable array.sbatch)\n"
      "array=${array%%;*}\n"
      "merge=$(sbatch --parsable --dependency=afterok:${array} --kill-on-invalid-dep=yes merge.sbatch)\n"
      "merge=${merge%%;*}\n"
      "echo \"array ${array} merge ${merge}\" >> submitted.txt\n"
      "echo \"submitted: array job ${array} (" +
      tasks + " tasks), merge job ${merge} after it; logs in $(pwd)/logs\"\n";
  create_output_folder(out / "logs", "--out");
  std::error_code error;
  write_text_atomically(out / "array.sbatch", array);
  write_text_atomically(out / "merge.sbatch", merge);
  write_text_atomically(out / "submit.sh", submit);
  for (const char* name : {"array.sbatch", "merge.sbatch", "submit.sh"})
    fs::permissions(out / name, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                    fs::perm_options::add, error);
  std::printf("wrote %s/array.sbatch (%d tasks), merge.sbatch and submit.sh\n", out.c_str(), options.tasks);
  std::fflush(stdout);
}

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string folders = path;
  for (size_t start = 0; start <= folders.size();) {
    const size_t end = std::min(folders.find(':', start), folders.size());
    const fs::path candidate = fs::path(folders.substr(start, end - start)) / program;
    if (access(candidate.c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

void submit(const fs::path& out) {
  if (!on_path("sbatch"))
    throw InputError("--submit: sbatch is not on PATH; expected Slurm's client (Debian: slurm-client), or run " +
                     (out / "submit.sh").string() + " where it is");
  const int status = std::system(("bash " + shell_word((out / "submit.sh").string())).c_str());
  if (status != 0) {
    std::fprintf(stderr, "fovlab: %s failed (exit %d); nothing more was submitted\n", (out / "submit.sh").c_str(),
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    throw CommandExit{1};
  }
}

// This process's command line as given (/proc/self/cmdline), for the scripts' header.
std::string invocation_text() {
  const std::optional<std::string> bytes = read_file_if_regular("/proc/self/cmdline", uint64_t(1) << 20);
  std::string text = "fovlab";
  if (!bytes) return text + " slurm";
  size_t start = bytes->find('\0');  // past argv[0]
  while (start != std::string::npos && start + 1 < bytes->size()) {
    const size_t end = bytes->find('\0', start + 1);
    const std::string word = bytes->substr(start + 1, end == std::string::npos ? std::string::npos : end - start - 1);
    text += " " + shell_word(word);
    start = end;
  }
  return text;
}

void add_slurm_flags(CLI::App& command, SlurmOptions& options) {
  command.add_option("--tasks", options.tasks, "N: tasks in the job array (each does 1/N of the work)")->required();
  command.add_option("--partition", options.partition, "Slurm partition (#SBATCH --partition)");
  command.add_option("--account", options.account, "Slurm account (#SBATCH --account)");
  command.add_option("--gpus-per-task", options.gpus_per_task, "GPUs per task, optionally typed: 1, a100:1");
  command.add_option("--cpus-per-task", options.cpus_per_task, "CPUs per task (default 1)");
  command.add_option("--time-limit", options.time_limit, "Each job's time limit (#SBATCH --time: 30, 2:00:00, 1-12)");
  command.add_option("--mem", options.mem, "Memory per node (#SBATCH --mem: 16G)");
  command.add_option("--max-requeue", options.max_requeue,
                     "Times a task killed by a signal requeues itself and resumes (default 3)");
  command.add_flag("--allow-lavapipe", options.allow_lavapipe,
                   "Let tasks render on a CPU Vulkan device (lavapipe) where a node has no GPU; default: refuse");
  add_output_option(command, "--out", options.out,
                    "Folder for the scripts and logs (default slurm/<config name>-prerender, or slurm/bench)",
                    {{OutputKind::folder}, kWritesIntoAFolder});
  command.add_option("--fovlab", options.fovlab, "The fovlab binary the tasks run (default this one)");
  command.add_flag("--submit", options.submit, "Submit with sbatch (submit.sh) once written");
}

struct PrerenderJobOptions {
  SlurmOptions slurm;
  std::string config;
  std::string cache = kDefaultCacheRoot.string();
  std::string device;
};

void run_slurm_prerender(const PrerenderJobOptions& options) {
  for (const auto& [what, word] : {std::pair<std::string, std::string>{"CONFIG", options.config},
                                   {"--cache", options.cache},
                                   {"--device", options.device},
                                   {"--fovlab", options.slurm.fovlab}})
    check_script_word(what, word);
  const size_t frames = prerender_frame_jobs(options.config).size();
  check_slurm_flags(options.slurm, int(std::min<size_t>(frames, 100000)),
                    std::to_string(frames) + " frames of " + options.config);
  const fs::path out =
      absolute_text(options.slurm.out.empty() ? "slurm/" + fs::path(options.config).stem().string() + "-prerender"
                                              : options.slurm.out);
  std::string common = shell_word(fovlab_binary(options.slurm)) + " prerender " +
                       shell_word(absolute_text(options.config)) + " --cache " +
                       shell_word(absolute_text(options.cache));
  if (!options.device.empty()) common += " --device " + shell_word(options.device);
  Job job;
  job.kind = "prerender";
  job.what =
      "renders frames I, I + N, ... of " + options.config + " into the cache; a rerun renders only what is missing.";
  job.task_command = common + " --shard \"${task}/" + std::to_string(options.slurm.tasks) + "\"" +
                     (options.slurm.allow_lavapipe ? "" : " --require-gpu");
  job.merge_what = "checks that every frame is in the cache and matches its .sha256 (exit 1 lists those that do not).";
  job.merge_command = common + " --verify";
  write_job(options.slurm, invocation_text(), job, out);
  if (options.slurm.submit) submit(out);
}

// fovlab slurm bench's own flags are SlurmOptions; every other word is a bench flag, checked here as
// fovlab bench would check it, then passed on to the tasks as given.
void run_slurm_bench(const SlurmOptions& slurm, const std::vector<std::string>& bench_words) {
  for (const std::string& word : bench_words) check_script_word("bench flag " + word.substr(0, 40), word);
  check_script_word("--fovlab", slurm.fovlab);
  BenchFlags bench = parse_bench_flags(bench_words, "bench flags");
  for (const auto& [flag, given] :
       {std::pair{"--json", !bench.json.empty()}, std::pair{"--out-dir", !bench.out_dir.empty()},
        std::pair{"--cells", !bench.cells.empty()}})
    if (given)
      throw InputError(std::string(flag) +
                       ": set by fovlab slurm bench (each task writes parts/part-I.json; the "
                       "merge job writes bench.json and report/); leave it out");
  const fs::path out = absolute_text(slurm.out.empty() ? "slurm/bench" : slurm.out);
  bench.json = out / "parts" / "part-0.json";
  bench.cells = "0/1";                                      // a part's plan is the sweep's
  const fovlab::bench::BenchPlan plan = plan_bench(bench);  // every bench flag checked before anything is written,
  fovlab::bench::load_bench_scenes(plan);                   // the scenes and the memory too
  const size_t units = bench.scenes.size() * plan.times_s.size() * bench.spps.size();
  check_slurm_flags(slurm, int(std::min<size_t>(units, 100000)),
                    std::to_string(units) + " (scene, time, spp) units of the sweep");

  std::string flags;
  for (const std::string& word : bench_words) flags += " " + shell_word(word);
  const std::string binary = shell_word(fovlab_binary(slurm));
  const std::string tasks = std::to_string(slurm.tasks);
  Job job;
  job.kind = "bench";
  job.what = "measures units I, I + N, ... of the sweep's (scene, time, spp) units into parts/part-I.json.";
  job.task_command = "mkdir -p " + shell_word((out / "parts").string()) + "\n" + binary + " bench" + flags +
                     " --cells \"${task}/" + tasks + "\" --json " + shell_word((out / "parts").string()) +
                     "/part-\"${task}\".json" + (slurm.allow_lavapipe || bench.require_gpu ? "" : " --require-gpu");
  job.merge_what = "joins every task's part into the sweep's report (bench.json; report/ with table.md and charts).";
  // Timings are what a sweep measures: two tasks on one node would slow each other.
  job.exclusive = !slurm.share_nodes;
  job.merge_command = binary + " bench-merge " + shell_word((out / "parts").string()) + "/part-{0.." +
                      std::to_string(slurm.tasks - 1) + "}.json --json " + shell_word((out / "bench.json").string()) +
                      " --out-dir " + shell_word((out / "report").string());
  write_job(slurm, invocation_text(), job, out);
  if (slurm.submit) submit(out);
}

}  // namespace

void add_slurm_command(CLI::App& app) {
  CLI::App* slurm = app.add_subcommand(
      "slurm",
      "Run a pre-render or a benchmark sweep on a Slurm cluster: a job array and a merge job (docs/scale-out.md)");
  slurm->require_subcommand(1);

  auto prerender = std::make_shared<PrerenderJobOptions>();
  CLI::App* prerender_command = slurm->add_subcommand(
      "prerender",
      "Write (and --submit) a job array whose task I runs fovlab prerender CONFIG --shard I/N, then --verify");
  prerender_command->add_option("config", prerender->config, "Study config (TOML) with pt or fpt stimuli")->required();
  add_output_option(*prerender_command, "--cache", prerender->cache,
                    "Pre-render cache folder, on a file system every node shares (default stimuli/cache)",
                    {{OutputKind::folder}, kCacheFolder});
  prerender_command->add_option("--device", prerender->device, "Vulkan device of each task: index or part of its name");
  add_slurm_flags(*prerender_command, prerender->slurm);
  prerender_command->callback([prerender] { run_slurm_prerender(*prerender); });

  auto bench = std::make_shared<SlurmOptions>();
  CLI::App* bench_command = slurm->add_subcommand(
      "bench", "Write (and --submit) a job array whose task I runs fovlab bench [flags] --cells I/N, then bench-merge");
  add_slurm_flags(*bench_command, *bench);
  bench_command->add_flag("--share-nodes", bench->share_nodes,
                          "Let tasks share a node (default: each its own, #SBATCH --exclusive, so their times do not "
                          "disturb each other)");
  bench_command->allow_extras();  // bench's own flags, passed on
  bench_command->footer(
      "Every other flag is one of fovlab bench's (fovlab bench --help): checked as bench checks it, "
      "then passed on to the tasks as given.");
  bench_command->callback([bench, bench_command] { run_slurm_bench(*bench, bench_command->remaining()); });
}

}  // namespace fovlab::app
