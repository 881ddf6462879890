#pragma once
// fovlab bench's results as the JSON it writes (--json, a part of --cells, --out-dir's bench.json):
// the one place where the typed results (bench/bench_results.h) become JSON. The tables and charts
// (bench/bench_outputs.h) read that JSON, so that a sweep merged from parts reports as one run does.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "bench/bench_results.h"

namespace fovlab::bench {

nlohmann::json unit_json(const UnitResult& unit);  // a row of "rows"
nlohmann::json cell_json(const CellResult& cell);  // a cell of "cells"
// The whole report: the settings, "rows", "cells", and with --cells the "part".
nlohmann::json bench_report_json(const BenchReport& report);

// A part's report (--cells I/N) written to `path`, and the line saying so; bench-merge joins the parts.
void write_bench_part(const BenchReport& report, const std::filesystem::path& path);

}  // namespace fovlab::bench
