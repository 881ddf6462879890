#include "bench/bench_parts.h"

#include <map>
#include <optional>

#include "core/input_error.h"

namespace fovlab::bench {

namespace {

const char* const kExpectedPart = "expected the JSON of fovlab bench --cells I/N --json";

int part_field(const PartReport& part, const char* key) {
  const nlohmann::json& value = part.report["part"][key];
  if (!value.is_number_integer()) throw InputError(part.path + ": \"part\"." + key + " is not a whole number; " + kExpectedPart);
  return value.get<int>();
}

std::string part_text(int index, int count) { return std::to_string(index) + "/" + std::to_string(count); }

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
    const int index = part_field(part, "index");
    const int part_count = part_field(part, "count");
    const int part_units = part_field(part, "units");
    if (part_count < 1 || index < 0 || index >= part_count || part_units < 0)
      throw InputError(part.path + ": \"part\" " + part_text(index, part_count) + " of " + std::to_string(part_units) +
                       " units; expected 0 <= index < count");
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
        if (!value.is_object() || !row.is_object() || value.value(key, nlohmann::json()) != row.value(key, nlohmann::json()))
          throw InputError(part.path + ": cell " + std::to_string(cell) + "'s \"" + key + "\" is not its unit's (row " +
                           std::to_string(local) + "); expected the cells of each unit after one another");
      merged["cells"].push_back(value);
    }
    merged["rows"].push_back(row);
  }
  return merged;
}

}  // namespace fovlab::bench
