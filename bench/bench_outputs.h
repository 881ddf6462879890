#pragma once
// fovlab bench's last step, shared with bench-merge: from a sweep's report alone (its "rows" and
// "cells" and the sweep's settings), the Pareto fronts, the tables printed, and the files: --json,
// and --out-dir's bench.json, table.md and charts. So a sweep run in parts and merged ends exactly as
// one run does.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace fovlab::bench {

// Marks the Pareto fronts of every cell in `report` (per scene), prints the summary tables (with the
// per-row table first unless `rows_printed`: bench printed each row as it was measured), and writes
// `json` and `out_dir`'s files when they are not empty.
// Writes `text` to stdout at once (a sweep's rows appear as they are measured).
void print_now(const std::string& text);

void finish_sweep(nlohmann::json& report, bool rows_printed, const std::filesystem::path& json,
                  const std::filesystem::path& out_dir);

}  // namespace fovlab::bench
