#pragma once
// trials.csv: one row a complete trial, tidy (one value a cell, a header row, RFC 4180 quoting), so
// pandas.read_csv and R's read.csv take it as is. Columns in docs/log-schema.md.
#include <string>
#include <vector>

namespace fovlab {

// The CSV text for these logs (complete trials only; a torn last line is ignored and reported on
// stderr). Throws InputError for a log that cannot be read.
std::string export_trials_csv(const std::vector<std::string>& log_paths);

}  // namespace fovlab
