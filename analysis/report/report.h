#pragma once
// The files `fovlab analyze` writes for an AnalysisResult, under one folder:
//   thresholds.json    every threshold, fit, condition and what was left out (docs/analysis.md)
//   conditions.csv     one row a condition (tidy, RFC 4180)
//   participants.csv   one row a participant and group threshold
//   *.svg              the plots (svg_chart.h)
//   report.html        one self-contained page: the tables and the plots inline
// Every file is written atomically (core/atomic_file.h).
#include <string>
#include <vector>

#include "analysis/study/analysis_result.h"

namespace fovlab::analysis {

// Returns the paths written, in order.
std::vector<std::string> write_analysis_report(const AnalysisResult& result, const std::string& out_dir);

}  // namespace fovlab::analysis
