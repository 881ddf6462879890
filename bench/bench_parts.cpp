#include "bench/bench_parts.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <map>
#include <optional>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab::bench {

namespace {

const char* const kExpectedPart = "expected the JSON of fovlab bench --cells I/N --json";

// "part".KEY, a whole number; one beyond 64 bits reads as the largest (every check refuses it, and
// messages quote the part's own text).
int64_t part_field(const PartReport& part, const char* key) {
  const nlohmann::json value = part.report["part"].value(key, nlohmann::json());
  if (!value.is_number_integer())
    throw InputError(part.path + ": \"part\"." + key + " is not a whole number; " + kExpectedPart);
  if (value.is_number_unsigned())
    return int64_t(std::min<uint64_t>(value.get<uint64_t>(), uint64_t(std::numeric_limits<int64_t>::max())));
  return value.get<int64_t>();
}

// "I/N of U units" as the part writes them (exact integers, however large).
std::string part_numbers_text(const PartReport& part) {
  const nlohmann::json& numbers = part.report["part"];
  return numbers["index"].dump() + "/" + numbers["count"].dump() + " of " + numbers["units"].dump() + " units";
}

std::string part_text(int index, int count) { return std::to_string(index) + "/" + std::to_string(count); }

enum class Kind { text, number, number_or_null, object };

bool is_kind(const nlohmann::json& value, Kind kind) {
  switch (kind) {
    case Kind::text:
      return value.is_string();
    case Kind::number:
      return value.is_number();
    case Kind::number_or_null:
      return value.is_number() || value.is_null();  // PSNR of identical frames: null
    case Kind::object:
      return value.is_object();
  }
  return false;
}

// `object` (at `where` in the part) has every key, each of its kind: what the tables and charts read
// (bench/bench_report.h, bench/bench_outputs.h), so a part edited by hand or cut short is refused
// naming the file and the field rather than read past what it holds.
void require(const PartReport& part, const nlohmann::json& object, const std::string& where,
             std::initializer_list<const char*> keys, Kind kind) {
  for (const char* key : keys)
    if (!object.is_object() || !object.contains(key) || !is_kind(object[key], kind))
      throw InputError(part.path + ": " + (where.empty() ? "" : where + ".") + key + " is missing or not " +
                       (kind == Kind::text     ? "text"
                        : kind == Kind::object ? "an object"
                                               : "a number") +
                       "; " + kExpectedPart);
}

// `object`[key], a number already, as a GPU time of a frame: from 0 to kMaxFrameGpuMs.
void require_time(const PartReport& part, const nlohmann::json& object, const std::string& where, const char* key) {
  const double ms = object[key].get<double>();
  if (!(std::isfinite(ms) && ms >= 0.0 && ms <= kMaxFrameGpuMs))
    throw InputError(part.path + ": " + where + "." + key + " is " + object[key].dump() +
                     "; expected a GPU time in milliseconds from 0 to " + std::to_string(int64_t(kMaxFrameGpuMs)) +
                     " (a day)");
}

// `object`[key], a number already, as a ratio of times or a count: finite and at least 0.
void require_not_negative(const PartReport& part, const nlohmann::json& object, const std::string& where,
                          std::initializer_list<const char*> keys) {
  for (const char* key : keys) {
    const double value = object[key].get<double>();
    if (!(std::isfinite(value) && value >= 0.0))
      throw InputError(part.path + ": " + where + "." + key + " is " + object[key].dump() +
                       "; expected a finite number of at least 0");
  }
}

void require_runs(const PartReport& part, const nlohmann::json& runs, const std::string& where) {
  require(part, runs, where, {"median_gpu_ms", "steps_per_pixel", "capped_rays"}, Kind::number);
  require(part, runs, where, {"median_pass_gpu_ms"}, Kind::object);
  require_time(part, runs, where, "median_gpu_ms");
  require_not_negative(part, runs, where, {"steps_per_pixel"});
  const nlohmann::json& capped = runs["capped_rays"];
  if (!capped.is_number_integer() ||
      (!capped.is_number_unsigned() && capped.get<int64_t>() < 0))  // the tables print a count
    throw InputError(part.path + ": " + where + ".capped_rays is " + capped.dump() +
                     "; expected a whole number of rays, at least 0");
  for (const auto& [pass, ms] : runs["median_pass_gpu_ms"].items()) {
    require(part, runs["median_pass_gpu_ms"], where + ".median_pass_gpu_ms", {pass.c_str()}, Kind::number);
    require_time(part, runs["median_pass_gpu_ms"], where + ".median_pass_gpu_ms", pass.c_str());
  }
}

void require_unit(const PartReport& part, const nlohmann::json& row, size_t row_index, const nlohmann::json& cells,
                  size_t first_cell, size_t cell_count) {
  const std::string at = "rows[" + std::to_string(row_index) + "]";
  require(part, row, at, {"scene"}, Kind::text);
  require(part, row, at, {"spp", "time_s"}, Kind::number);
  require_runs(part, row.value("gt", nlohmann::json()), at + ".gt");
  require(part, row, at, {"floor"}, Kind::object);
  require(part, row["floor"], at + ".floor", {"median_gpu_ms"}, Kind::number);
  require_time(part, row["floor"], at + ".floor", "median_gpu_ms");
  if (row.contains("ipr")) {
    require_runs(part, row["ipr"], at + ".ipr");
    require(part, row, at, {"speedup", "ssim", "flip"}, Kind::number);
    require(part, row, at, {"psnr_db", "fpsnr_db"}, Kind::number_or_null);
    require_not_negative(part, row, at, {"speedup"});
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
    require(part, cell, where, {"median_pass_gpu_ms"}, Kind::object);
    require_time(part, cell, where, "median_gpu_ms");
    require_time(part, cell, where, "gt_median_gpu_ms");
    for (const auto& [pass, ms] : cell["median_pass_gpu_ms"].items()) {
      require(part, cell["median_pass_gpu_ms"], where + ".median_pass_gpu_ms", {pass.c_str()}, Kind::number);
      require_time(part, cell["median_pass_gpu_ms"], where + ".median_pass_gpu_ms", pass.c_str());
    }
    require_not_negative(part, cell, where, {"speedup", "steps_per_pixel", "top_level_share", "refreshed_share"});
    if (cell["method"] == "fipr") require(part, cell, where, {"refresh", "fovea_deg"}, Kind::number);
    if (cell.contains("sampling")) {
      require(part, cell, where, {"sampling"}, Kind::object);
      require(part, cell["sampling"], where + ".sampling", {"theoretical_speedup", "effective_speedup", "shaded_share"},
              Kind::number);
      require_not_negative(part, cell["sampling"], where + ".sampling",
                           {"theoretical_speedup", "effective_speedup", "shaded_share"});
    }
    if (cell.contains("focal_share_x") || cell.contains("focal_share_y"))
      require(part, cell, where, {"focal_share_x", "focal_share_y"}, Kind::number);
  }
}

}  // namespace

nlohmann::json part_json(const SweepPart& part, int units) {
  return {{"index", part.index}, {"count", part.count}, {"units", units}};
}

nlohmann::json merge_bench_parts(const std::vector<PartReport>& parts, const PartLayout& layout_of) {
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
    const int64_t index_given = part_field(part, "index");
    const int64_t count_given = part_field(part, "count");
    const int64_t units_given = part_field(part, "units");
    if (count_given < 1 || count_given > 100000 || index_given < 0 || index_given >= count_given || units_given < 0 ||
        units_given > 100000000)
      throw InputError(part.path + ": \"part\" " + part_numbers_text(part) +
                       "; expected 0 <= index < count <= 100000 and at most 100000000 units");
    const int index = int(index_given);
    if (by_index.empty()) {
      count = int(count_given);
      units = int(units_given);
    } else if (count_given != count || units_given != units) {
      throw InputError(part.path + ": part " + part_numbers_text(part) + ", but " + by_index.begin()->second->path +
                       " is of " + std::to_string(count) + " parts of " + std::to_string(units) +
                       " units; expected parts of one sweep");
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

  // The sweep the parts' flags plan (their "command", the same in every part): its units, the cells
  // of each, and the settings the tables print.
  const SweepLayout layout = layout_of(first);
  const std::string planned = " (as its \"command\" plans the sweep)";
  if (units != layout.units())
    throw InputError(first.path + ": \"part\".units is " + std::to_string(units) + "; expected " +
                     std::to_string(layout.units()) + ", the sweep's " + std::to_string(layout.scenes.size()) +
                     " scenes x " + std::to_string(layout.times_s.size()) + " times x " +
                     std::to_string(layout.spps.size()) + " spp" + planned);
  for (const auto& [key, value] :
       {std::pair{"width", layout.width}, std::pair{"height", layout.height}, std::pair{"repeats", layout.repeats}})
    if (first.report[key] != nlohmann::json(value))
      throw InputError(first.path + ": " + key + " is " + first.report[key].dump() + "; expected " +
                       std::to_string(value) + planned);
  // What the tables and charts group the cells by: the scene times, whether FIPR was swept, RMFR's pairs.
  nlohmann::json times_s = nlohmann::json::array();
  for (float time_s : layout.times_s) times_s.push_back(double(time_s));
  if (first.report["times_s"] != times_s)
    throw InputError(first.path + ": times_s is " + first.report["times_s"].dump().substr(0, 80) + "; expected " +
                     times_s.dump() + planned);
  const bool fipr = std::any_of(layout.unit_cells.begin(), layout.unit_cells.end(),
                                [](const PlannedCell& cell) { return cell.method == BenchMethod::fipr; });
  if (first.report.contains("fipr") != fipr)
    throw InputError(first.path + ": " + (fipr ? "no \"fipr\" object" : "a \"fipr\" object") + "; expected " +
                     (fipr ? "one: the sweep has FIPR cells" : "none: the sweep has no FIPR cell") + planned);
  const nlohmann::json focal_shares = {{"x", layout.focal_shares_x}, {"y", layout.focal_shares_y}};
  if (layout.focal_shares_x.empty() ? first.report.contains("sampling_focal_shares")
                                    : first.report.value("sampling_focal_shares", nlohmann::json()) != focal_shares)
    throw InputError(
        first.path + ": sampling_focal_shares is " +
        (first.report.contains("sampling_focal_shares") ? first.report["sampling_focal_shares"].dump().substr(0, 80)
                                                        : std::string("missing")) +
        "; expected " +
        (layout.focal_shares_x.empty() ? "none: the sweep has no sampling model" : focal_shares.dump()) + planned);
  std::string cell_methods;
  for (const PlannedCell& cell : layout.unit_cells)
    cell_methods += (cell_methods.empty() ? "" : ", ") + std::string(bench_method_name(cell.method));
  const size_t cells_per_unit = layout.unit_cells.size();

  // Each part holds exactly the units of its index, each with exactly its planned cells.
  for (const auto& [index, part] : by_index) {
    const SweepPart shape{index, count};
    const nlohmann::json& rows = part->report["rows"];
    const nlohmann::json& cells = part->report["cells"];
    if (rows.size() != size_t(shape.units_held(units)))
      throw InputError(part->path + ": " + std::to_string(rows.size()) + " rows; expected " +
                       std::to_string(shape.units_held(units)) + ", one per unit of part " + part_text(index, count) +
                       " of " + std::to_string(units) + " units");
    if (cells.size() != rows.size() * cells_per_unit)
      throw InputError(part->path + ": " + std::to_string(cells.size()) + " cells for " + std::to_string(rows.size()) +
                       " units; expected " + std::to_string(cells_per_unit) + " a unit (" + cell_methods + ")" +
                       planned);
    for (size_t row_index = 0; row_index < rows.size(); ++row_index) {
      const nlohmann::json& row = rows[row_index];
      require_unit(*part, row, row_index, cells, row_index * cells_per_unit, cells_per_unit);
      // Part I of N holds units I, I + N, ...: the row's unit, and what the plan has there.
      const int unit = index + int(row_index) * count;
      const std::string held = " (unit " + std::to_string(unit) + " of the sweep: part " + part_text(index, count) +
                               " holds units " + std::to_string(index) + ", " + std::to_string(index) + " + " +
                               std::to_string(count) + ", ..., as its \"command\" plans the sweep)";
      const std::string at = "rows[" + std::to_string(row_index) + "]";
      if (row["scene"] != layout.scene_of(unit))
        throw InputError(part->path + ": " + at + ".scene is " + row["scene"].dump() + "; expected \"" +
                         layout.scene_of(unit) + "\"" + held);
      if (row["time_s"] != nlohmann::json(double(layout.time_of(unit))))
        throw InputError(part->path + ": " + at + ".time_s is " + row["time_s"].dump() + "; expected " +
                         exact_number_text(layout.time_of(unit)) + held);
      if (row["spp"] != nlohmann::json(layout.spp_of(unit)))
        throw InputError(part->path + ": " + at + ".spp is " + row["spp"].dump() + "; expected " +
                         std::to_string(layout.spp_of(unit)) + held);
      for (size_t planned_index = 0; planned_index < cells_per_unit; ++planned_index) {
        const size_t cell_index = row_index * cells_per_unit + planned_index;
        const nlohmann::json& cell = cells[cell_index];
        const std::string where = "cells[" + std::to_string(cell_index) + "]";
        for (const char* key : {"scene", "spp", "time_s"})
          if (cell[key] != row[key])
            throw InputError(part->path + ": " + where + "'s \"" + key + "\" is not its unit's (" + at +
                             "); expected the cells of each unit after one another");
        const PlannedCell& plan = layout.unit_cells[planned_index];
        const std::string nth = " (cell " + std::to_string(planned_index + 1) + " of every unit's " +
                                std::to_string(cells_per_unit) + ": " + cell_methods +
                                ", as its \"command\" plans "
                                "the sweep)";
        if (cell["method"] != bench_method_name(plan.method))
          throw InputError(part->path + ": " + where + ".method is " + cell["method"].dump().substr(0, 60) +
                           "; expected \"" + bench_method_name(plan.method) + "\"" + nth);
        const auto check = [&](const char* key, const auto& value) {
          if (value && (!cell.contains(key) || cell[key] != nlohmann::json(*value)))
            throw InputError(part->path + ": " + where + "." + key + " is " +
                             (cell.contains(key) ? cell[key].dump().substr(0, 60) : std::string("missing")) +
                             "; expected " + exact_number_text(double(*value)) + nth);
        };
        check("refresh", plan.refresh);
        check("fovea_deg", plan.fovea_deg);
        check("focal_share_x", plan.focal_share_x);
        check("focal_share_y", plan.focal_share_y);
      }
    }
  }

  nlohmann::json merged = first.report;
  merged.erase("part");
  merged["rows"] = nlohmann::json::array();
  merged["cells"] = nlohmann::json::array();
  for (int unit = 0; unit < units; ++unit) {
    const PartReport& part = *by_index.at(unit % count);
    const size_t local = size_t(unit / count);
    merged["rows"].push_back(part.report["rows"][local]);
    for (size_t cell = local * cells_per_unit; cell < (local + 1) * cells_per_unit; ++cell)
      merged["cells"].push_back(part.report["cells"][cell]);
  }
  return merged;
}

}  // namespace fovlab::bench
