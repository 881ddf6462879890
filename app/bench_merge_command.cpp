// fovlab bench-merge PART.json... [--json OUT] [--out-dir DIR]: joins the parts of a sweep run as
// fovlab bench --cells I/N (on a cluster: fovlab slurm bench) into the report one run of the whole
// sweep writes: the same JSON, tables, charts and Pareto fronts (bench/bench_parts.h,
// bench/bench_outputs.h). A file that is not a part, a part missing or given twice, parts of another
// sweep or device, or a part whose rows and cells are not those its index holds in the sweep its
// flags plan (a relabelled index, a method or variant not planned, a time out of range) is one line
// naming the file and the field, exit code 2, and nothing written.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/bench_flags.h"
#include "app/commands.h"
#include "app/output_options.h"
#include "bench/bench.h"
#include "core/input_error.h"
#include "core/input_file.h"

namespace fovlab::app {

namespace {

struct BenchMergeOptions {
  std::vector<std::string> parts;
  std::filesystem::path json;
  std::filesystem::path out_dir;
};

// A part's JSON is a few hundred bytes a cell; anything far larger is not one.
constexpr std::uint64_t kMaxPartBytes = 512 * kMebibyte;
const char* const kPartExpected = "a part's JSON (bench --cells I/N --json)";

bench::PartReport read_part(const std::string& path) {
  const std::string text = read_input_file(path, kPartExpected, kMaxPartBytes);
  try {
    return {path, nlohmann::json::parse(text)};
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path + ": not JSON (at byte " + std::to_string(e.byte) + "): expected " + kPartExpected);
  }
}

// The sweep a part's flags (its "command") plan, rebuilt as fovlab bench plans it.
bench::SweepLayout part_layout(const bench::PartReport& part) {
  try {
    return bench::sweep_layout(plan_bench(parse_sweep_command(part.report["command"].get<std::string>())));
  } catch (const InputError& error) {
    throw InputError(part.path + ": \"command\": " + error.what() +
                     "; expected the command of the sweep, as bench writes it");
  }
}

void run_bench_merge(const BenchMergeOptions& options) {
  std::vector<bench::PartReport> parts;
  for (const std::string& path : options.parts) parts.push_back(read_part(path));
  nlohmann::json report = bench::merge_bench_parts(parts, part_layout);
  if (!options.out_dir.empty()) create_output_folder(options.out_dir, "--out-dir");
  std::printf("fovlab bench-merge: %zu parts, %zu (scene, time, spp) units, %zu cells, measured on %s\n", parts.size(),
              report["rows"].size(), report["cells"].size(), report["device"].get<std::string>().c_str());
  bench::finish_sweep(report, false, options.json, options.out_dir);
}

}  // namespace

void add_bench_merge_command(CLI::App& app) {
  auto options = std::make_shared<BenchMergeOptions>();
  CLI::App* command = app.add_subcommand(
      "bench-merge", "Join the parts of a sweep run with bench --cells I/N into one report (JSON, tables, charts)");
  command->add_option("parts", options->parts, "Every part's JSON (bench --cells I/N --json), in any order")
      ->required();
  add_output_option(*command, "--json", options->json, "Write the sweep's JSON, as one run of bench --json writes it",
                    {{OutputKind::file}, kReplacesAFile});
  add_output_option(*command, "--out-dir", options->out_dir,
                    "Write bench.json, table.md and the Pareto charts (SVG) here",
                    {{OutputKind::folder}, kWritesIntoAFolder});
  command->callback([options] { run_bench_merge(*options); });
}

}  // namespace fovlab::app
