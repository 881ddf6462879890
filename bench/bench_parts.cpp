#include "bench/bench_parts.h"

#include <initializer_list>
#include <map>
#include <optional>

#include "core/input_error.h"

namespace fovlab::bench {

namespace {

const char* const kExpectedPart = "expected the JSON of fovlab bench --cells I/N --json";

int part_field(const PartReport& part, const char* key) {
  const nlohmann::json value = part.report["part"].value(key, nlohmann::json());
  if (!value.is_number_integer()) throw InputError(part.path + ": \"part\"." + key + " is not a whole number; " + kExpectedPart);
  return value.get<int>();
}

std::string part_text(int index, int count) { return std::to_string(index) + "/" + std::to_string(count); }

enum class Kind { text, number, number_or_null, object };

bool is_kind(const nlohmann::json& value, Kind kind) {
  switch (kind) {
    case Kind::text: return value.is_string();
    case Kind::number: return value.is_number();
    case Kind::number_or_null: return value.is_number() || value.is_null();  // PSNR of identical frames: null
    case Kind::object: return value.is_object();
  }
  return false;
}

// `object` (at `where` in the part) has every key, each of its kind: what the tables and charts read
// (bench/bench_report.h, app/bench_outputs.h), so a part edited by hand or cut short is refused
// naming the file and the field rather than read past what it holds.
void require(const PartReport& part, const nlohmann::json& object, const std::string& where,
             std::initializer_list<const char*> keys, Kind kind) {
  for (const char* key : keys)
    if (!object.is_object() || !object.contains(key) || !is_kind(object[key], kind))
      throw InputError(part.path + ": " + (where.empty() ? "" : where + ".") + key + " is missing or not " +
                       (kind == Kind::text ? "text" : kind == Kind::object ? "an object" : "a number") + "; " +
                       kExpectedPart);
}

void require_runs(const PartReport& part, const nlohmann::json& runs, const std::string& where) {
  require(part, runs, where, {"median_gpu_ms", "steps_per_pixel", "capped_rays"}, Kind::number);
  require(part, runs, where, {"median_pass_gpu_ms"}, Kind::object);
  for (const auto& [pass, ms] : runs["median_pass_gpu_ms"].items())
    require(part, runs["median_pass_gpu_ms"], where + ".median_pass_gpu_ms", {pass.c_str()}, Kind::number);
}

void require_unit(const PartReport& part, const nlohmann::json& row, size_t row_index, const nlohmann::json& cells,
                  size_t first_cell, size_t cell_count) {
  const std::string at = "rows[" + std::to_string(row_index) + "]";
  require(part, row, at, {"scene"}, Kind::text);
  require(part, row, at, {"spp", "time_s"}, Kind::number);
  require_runs(part, row.value("gt", nlohmann::json()), at + ".gt");
  require(part, row, at, {"floor"}, Kind::object);
  require(part, row["floor"], at + ".floor", {"median_gpu_ms"}, Kind::number);
  if (row.contains("ipr")) {
    require_runs(part, row["ipr"], at + ".ipr");
    require(part, row, at, {"speedup", "ssim", "flip"}, Kind::number);
    require(part, row, at, {"psnr_db", "fpsnr_db"}, Kind::number_or_null);
  }
  for (size_t index = first_cell; index < first_cell + cell_count; ++index) {
    const nlohmann::json& cell = cells[index];
    const std::string where = "cells[" + std::to_string(index) + "]";
    require(part, cell, where, {"method", "scene"}, Kind::text);
    require(part, cell, where,
            {"spp", "time_s", "median_gpu_ms", "gt_median_gpu_ms", "speedup", "steps_per_pixel", "top_level_share",
             "refreshed_share", "ssim", "flip"},
            Kind::number);
    require(part, cell, where, {"psnr_db", "fpsnr_db"}, Kind::number_or_null);
    if (cell["method"] == "fipr") require(part, cell, where, {"refresh", "fovea_deg"}, Kind::number);
    if (cell.contains("sampling")) {
      require(part, cell, where, {"sampling"}, Kind::object);
      require(part, cell["sampling"], where + ".sampling", {"theoretical_speedup", "effective_speedup", "shaded_share"},
              Kind::number);
    }
    if (cell.contains("focal_share_x") || cell.contains("focal_share_y"))
      require(part, cell, where, {"focal_share_x", "focal_share_y"}, Kind::number);
  }
}

}  // namespace

nlohmann::json part_json(const SweepPart& part, int units) {
  return {{"index", part.index}, {"count", part.count}, {"units", units}};
}

nlohmann::json merge_bench_parts(const std::vector<PartReport>& parts) {
  if (parts.empty()) throw InputError("bench-merge: no parts given; " + std::string(kExpectedPart));
  int count = 0;
  int units = 0;
  std::map<int, const PartReport*> by_index;
  for (const PartReport& part : parts) {
    if (!part.report.is_object() || !part.report.contains("part") || !part.report["part"].is_object())
      throw InputError(part.path + ": not a part of a sweep (no \"part\" object); " + kExpectedPart);
    for (const char* key : {"rows", "cells"})
      if (!part.report.contains(key) || !part.report[key].is_array())
        throw InputError(part.path + ": no \"" + key + "\" array; " + kExpectedPart);
    require(part, part.report, "", {"device", "command"}, Kind::text);
    require(part, part.report, "", {"width", "height", "repeats"}, Kind::number);
    require(part, part.report, "", {"metrics"}, Kind::object);
    require(part, part.report["metrics"], "metrics", {"flip_pixels_per_degree"}, Kind::number);
    if (!part.report.contains("times_s") || !part.report["times_s"].is_array())
      throw InputError(part.path + ": no \"times_s\" array; " + std::string(kExpectedPart));
    const int index = part_field(part, "index");
    const int part_count = part_field(part, "count");
    const int part_units = part_field(part, "units");
    if (part_count < 1 || part_count > 100000 || index < 0 || index >= part_count || part_units < 0 ||
        part_units > 100000000)
      throw InputError(part.path + ": \"part\" " + part_text(index, part_count) + " of " + std::to_string(part_units) +
                       " units; expected 0 <= index < count <= 100000");
    if (by_index.empty()) {
      count = part_count;
      units = part_units;
    } else if (part_count != count || part_units != units) {
      throw InputError(part.path + ": part " + part_text(index, part_count) + " of " + std::to_string(part_units) +
                       " units, but " + by_index.begin()->second->path + " is of " + std::to_string(count) +
                       " parts of " + std::to_string(units) + " units; expected parts of one sweep");
    }
    if (const auto seen = by_index.find(index); seen != by_index.end())
      throw InputError(part.path + ": part " + part_text(index, count) + " again (also " + seen->second->path +
                       "); expected each part once");
    by_index.emplace(index, &part);
  }
  std::string missing;
  for (int index = 0; index < count; ++index)
    if (!by_index.count(index)) missing += (missing.empty() ? "" : ", ") + part_text(index, count);
  if (!missing.empty())
    throw InputError("bench-merge: part" + std::string(missing.find(',') == std::string::npos ? " " : "s ") + missing +
                     " missing (" + std::to_string(parts.size()) + " of " + std::to_string(count) +
                     " given); expected every part of the sweep");

  // Everything but the units' results is the sweep's: the same in every part.
  const PartReport& first = *by_index.begin()->second;
  for (const auto& [index, part] : by_index) {
    for (const auto& [key, value] : part->report.items()) {
      if (key == "rows" || key == "cells" || key == "part") continue;
      if (!first.report.contains(key) || first.report[key] != value)
        throw InputError(part->path + ": \"" + key + "\" differs from " + first.path +
                         "'s; expected parts of one sweep (the same command on the same device)");
    }
    for (const auto& [key, value] : first.report.items())
      if (!part->report.contains(key))
        throw InputError(part->path + ": no \"" + key + "\" (" + first.path + " has it); expected parts of one sweep");
  }

  // Cells per unit: the same in every part that holds a unit.
  std::optional<size_t> cells_per_unit;
  for (const auto& [index, part] : by_index) {
    const SweepPart shape{index, count};
    const size_t rows = part->report["rows"].size();
    const size_t cells = part->report["cells"].size();
    if (rows != size_t(shape.units_held(units)))
      throw InputError(part->path + ": " + std::to_string(rows) + " rows; expected " +
                       std::to_string(shape.units_held(units)) + ", one per unit of part " + part_text(index, count) +
                       " of " + std::to_string(units) + " units");
    if (rows == 0) continue;
    if (cells % rows != 0 || (cells_per_unit && *cells_per_unit != cells / rows))
      throw InputError(part->path + ": " + std::to_string(cells) + " cells for " + std::to_string(rows) +
                       " units; expected the same cells for every unit of the sweep");
    cells_per_unit = cells / rows;
    for (size_t row = 0; row < rows; ++row)
      require_unit(*part, part->report["rows"][row], row, part->report["cells"], row * *cells_per_unit, *cells_per_unit);
  }

  nlohmann::json merged = first.report;
  merged.erase("part");
  merged["rows"] = nlohmann::json::array();
  merged["cells"] = nlohmann::json::array();
  for (int unit = 0; unit < units; ++unit) {
    const PartReport& part = *by_index.at(unit % count);
    const size_t local = size_t(unit / count);
    const nlohmann::json& row = part.report["rows"][local];
    for (size_t cell = local * *cells_per_unit; cell < (local + 1) * *cells_per_unit; ++cell) {
      const nlohmann::json& value = part.report["cells"][cell];
      for (const char* key : {"scene", "spp", "time_s"})
        if (value[key] != row[key])
          throw InputError(part.path + ": cell " + std::to_string(cell) + "'s \"" + key + "\" is not its unit's (row " +
                           std::to_string(local) + "); expected the cells of each unit after one another");
      merged["cells"].push_back(value);
    }
    merged["rows"].push_back(row);
  }
  return merged;
}

}  // namespace fovlab::bench
