#pragma once
// The files `fovlab analyze` writes for an AnalysisResult, under one folder:
//   headline.csv       one row a group: the number to publish, its interval, status and method
//   thresholds.json    every headline, threshold, fit, condition and what was left out (docs/analysis.md)
//   conditions.csv     one row a condition (tidy, RFC 4180)
//   participants.csv   one row a participant and group threshold (with its session's frame intervals)
//   *.svg              the plots (svg_chart.h)
//   report.html        one self-contained page: the tables and the plots inline
// Every file is written atomically (core/atomic_file.h); write_analysis_folder writes them as a set.
#include <string>
#include <vector>

#include "analysis/study/analysis_result.h"

namespace fovlab::analysis {

// Writes the files into `out_dir` (created when missing), each one atomically. Returns the paths
// written, in order.
std::vector<std::string> write_analysis_report(const AnalysisResult& result, const std::string& out_dir);

// Whether `out_dir` may receive an analysis, after removing what killed runs left beside it
// (core/atomic_file.h): nothing is there (or an empty folder), or an earlier analysis and `replace`.
// Otherwise InputError, one line naming the folder: an analysis is there and `replace` is false
// ("add --force"), or it holds anything write_analysis_report does not write (a session log, a
// subfolder, other files: never replaced, not even with --force), or it is a file.
void check_analysis_destination(const std::string& out_dir, bool replace);

// The report as one set: checks `out_dir` (check_analysis_destination), writes every file into a
// temporary folder beside it, then renames that folder into place (write_folder_atomically: a kill
// leaves the old analysis or the new one, never a mix). Returns the final paths, in order.
std::vector<std::string> write_analysis_folder(const AnalysisResult& result, const std::string& out_dir, bool replace);

}  // namespace fovlab::analysis
