// fovlab export: trials.csv (one row a complete trial) from one log or a study's results folder.
#include <cstdio>
#include <filesystem>
#include <optional>

#include "app/commands.h"
#include "app/output_options.h"
#include "core/atomic_file.h"
#include "core/input_error.h"
#include "core/output_guard.h"
#include "core/session_files.h"
#include "study/log/event_log.h"
#include "study/log/log_integrity.h"
#include "protocols/session/trials_export.h"

namespace fovlab::app {
namespace {

// Export writes trials.csv and steps.csv beside the log it reads by default: the only files of a
// participant's folder that a command other than the session writes.
const OutputTarget kExportTarget{OutputKind::file, {"trials.csv", "steps.csv"}};

struct ExportArguments {
  std::string input;
  std::string out;
  bool force = false;
  bool include_broken = false;
  std::string lab_key_path;
};

// trials.csv, and steps.csv beside it when the logs hold ramp steps or slider actions.
void export_trials(const ExportArguments& arguments) {
  namespace fs = std::filesystem;
  const std::string& input = arguments.input;
  std::string out = arguments.out;
  const std::vector<std::string> logs = find_session_logs(input);
  if (out.empty()) out = (fs::is_directory(input) ? fs::path(input) : fs::path(input).parent_path()) / "trials.csv";
  const fs::path steps_out = fs::path(out).parent_path() / (fs::path(out).stem().string() == "trials"
                                                                ? std::string("steps.csv")
                                                                : fs::path(out).stem().string() + "_steps.csv");
  const std::string flag = arguments.out.empty() ? "" : "--out";
  check_output_target(out, flag, kExportTarget);
  check_output_target(steps_out, flag, kExportTarget);
  // The names export owns in a participant's folder are its own only beside the one log it reads:
  // never another participant's (whose trials.csv it would replace, and whose steps.csv --force removes).
  const fs::path out_folder = resolved_output_path(out).parent_path();
  if (const std::string mark = participant_folder_mark(out_folder); !mark.empty()) {
    std::error_code error;
    const bool own_folder = logs.size() == 1 && fs::equivalent(fs::path(logs.front()).parent_path(), out_folder, error);
    if (!own_folder)
      throw InputError((flag.empty() ? out : flag + " " + out) + ": inside the participant's folder " +
                       out_folder.string() +
                       ", which is not the folder of the one log exported; expected a path outside participant folders "
                       "(or that log's own folder when exporting one log)");
  }
  if (fs::exists(out) && !arguments.force) throw InputError("--out: " + out + " exists (pass --force to replace it)");
  const std::optional<LabKey> lab_key = read_optional_lab_key(arguments.lab_key_path);
  const ExportedCsv csv =
      export_session_csvs(logs, ExportOptions{lab_key ? &*lab_key : nullptr, arguments.include_broken});
  const bool has_steps = csv.steps.find('\n') + 1 < csv.steps.size();  // more than the header
  if (has_steps && fs::exists(steps_out) && !arguments.force)
    throw InputError("--out: " + steps_out.string() + " exists (pass --force to replace it)");
  write_text_atomically(out, csv.trials);
  if (has_steps) {
    write_text_atomically(steps_out, csv.steps);
  } else if (fs::exists(steps_out)) {  // an earlier export's: it no longer goes with this trials.csv
    if (arguments.force) fs::remove(steps_out);
    std::fprintf(stderr, "fovlab: %s: from an earlier export, %s (these logs have no ramp steps or slider actions)\n",
                 steps_out.string().c_str(), arguments.force ? "removed" : "left as it was");
  }
  std::printf("%s%s: %zu log(s)\n", out.c_str(), has_steps ? (" and " + steps_out.string()).c_str() : "", logs.size());
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto arguments = std::make_shared<ExportArguments>();
  CLI::App* command = app.add_subcommand(
      "export", "Write trials.csv (one row a trial) and steps.csv (ramp steps, slider actions) from session logs");
  command->add_option("logs", arguments->input, "A session log, or a results folder (every events.jsonl under it)")
      ->required();
  add_output_option(*command, "--out", arguments->out,
                    "CSV file (default: trials.csv beside the log or in the folder); ramp steps and slider actions "
                    "go to steps.csv beside it (NAME_steps.csv for another name)",
                    {kExportTarget, "an existing file is replaced only with --force"});
  command->add_flag("--force", arguments->force, "Replace an existing CSV (never a session's file)");
  command->add_flag("--include-broken", arguments->include_broken,
                    "Export logs whose chain or seal is broken too (their rows say log_status broken)");
  command->add_option("--lab-key", arguments->lab_key_path,
                      "The lab key the sessions ran with: verify their seals' MACs");
  command->callback([arguments] { export_trials(*arguments); });
}

}  // namespace fovlab::app
