#pragma once
// trials.csv: one row a complete trial, tidy (one value a cell, a header row, RFC 4180 quoting), so
// pandas.read_csv and R's read.csv take it as is. Columns in docs/log-schema.md.
#include <string>
#include <vector>

namespace fovlab {

struct LabKey;

struct ExportOptions {
  const LabKey* lab_key = nullptr;  // verify keyed seals
  bool include_broken = false;      // export broken logs too (their rows say log_status "broken")
};

struct ExportedCsv {
  std::string trials;  // trials.csv: one row a complete trial
  std::string steps;   // steps.csv: one row an answer of a ramp step or slider action (long format)
};

// The CSV texts for these logs (complete trials only; a torn last line is ignored). Every log's
// chain and seals are checked, and the log against its own header (study/log/log_consistency.h:
// its config_hash, study and session_seed, its trials against the schedule): a broken log is an
// InputError unless include_broken; an unsealed one, or a keyed one read without its key ("MACs
// not checked (no key given)"), is exported and reported on stderr; the column log_status says
// which each row came from. Logs of one session are counted once (study/log/session_copies.h): a
// copy is left out and named on stderr; two that part are both broken.
// Throws InputError for a log that cannot be read.
ExportedCsv export_session_csvs(const std::vector<std::string>& log_paths, const ExportOptions& options = {});
// trials.csv alone.
std::string export_trials_csv(const std::vector<std::string>& log_paths, const ExportOptions& options = {});

}  // namespace fovlab
