// fovlab export: trials.csv (one row a complete trial) from one log or a study's results folder.
#include <cstdio>
#include <filesystem>

#include "app/commands.h"
#include "core/atomic_file.h"
#include "core/input_error.h"
#include "protocols/log/event_log.h"
#include "protocols/session/trials_export.h"

namespace fovlab::app {
namespace {

void export_trials(const std::string& input, std::string out, bool force) {
  namespace fs = std::filesystem;
  const std::vector<std::string> logs = find_session_logs(input);
  if (out.empty()) out = (fs::is_directory(input) ? fs::path(input) : fs::path(input).parent_path()) / "trials.csv";
  if (fs::exists(out) && !force) throw InputError("--out: " + out + " exists (pass --force to replace it)");
  const std::string csv = export_trials_csv(logs);
  write_text_atomically(out, csv);
  std::printf("%s: %zu log(s)\n", out.c_str(), logs.size());
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto input = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto force = std::make_shared<bool>(false);
  CLI::App* command = app.add_subcommand("export", "Write trials.csv (one row a trial) from session logs");
  command->add_option("logs", *input, "A session log, or a results folder (every events.jsonl under it)")->required();
  command->add_option("--out", *out, "CSV file (default: trials.csv beside the log or in the folder)");
  command->add_flag("--force", *force, "Replace an existing CSV");
  command->callback([input, out, force] { export_trials(*input, *out, *force); });
}

}  // namespace fovlab::app
