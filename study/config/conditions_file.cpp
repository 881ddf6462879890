#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/csv.h"
#include "core/input_error.h"
#include "core/input_file.h"
#include "core/number_text.h"
#include "core/toml_fields.h"
#include "study/config/config_reading.h"
#include "study/config/study_config.h"
#include "study/stimulus/render_method.h"

namespace fovlab::config_detail {

// [conditions] file: the conditions as a CSV file's rows (PsychoPy's conditions files). The header
// names the columns: `variant` (the condition's variant), the [levels] parameter (its level), and
// parameters of the test method (overrides, as a variant's table holds them; an empty cell leaves
// the parameter as the test method has it). A variant's rows differ in level only. The result is
// the variants (with their own levels) and the levels (every level of any row, ascending).
void read_conditions(const TomlFields& fields, const Reading& reading, StudyConfig& config) {
  const std::string file = fields.string("file");
  if (file.empty())  // else the config's folder, or a file named "", would be read in its place
    fields.fail("file", "expected the path of a conditions file (.csv, relative to the config's folder), got \"\"");
  fields.finish();
  std::filesystem::path path(file);
  if (path.is_relative()) path = std::filesystem::path(config.source_path).parent_path() / path;
  // A logged config's file is the header's conditions_csv, named so in messages.
  const std::string name =
      reading.logged_conditions_csv ? config.source_path + ": conditions_csv" : path.lexically_normal().string();
  if (reading.logged_conditions_csv) {
    if (reading.logged_conditions_csv->empty())
      fields.fail("file",
                  "the log's header holds no conditions_csv (expected the conditions file's text beside the config's)");
    if (reading.logged_conditions_csv->size() > kMaxConditionsBytes)
      throw InputError(name + ": " + std::to_string(reading.logged_conditions_csv->size()) +
                       " bytes: expected a conditions file of at most " + byte_size_text(kMaxConditionsBytes));
    config.conditions_csv = *reading.logged_conditions_csv;
  } else {
    config.conditions_csv = read_input_file(name, "a conditions file (.csv)", kMaxConditionsBytes);
  }
  config.conditions_path = file;
  const std::vector<CsvRow> rows = read_csv_rows(config.conditions_csv, name);
  const auto fail = [&](int line, const std::string& what) {
    throw InputError(name + ":" + std::to_string(line) + ": " + what);
  };
  if (rows.size() < 2) fail(rows.empty() ? 1 : rows.front().line, "expected a header row and at least one condition");
  if (rows.size() - 1 > kMaxConditionsRows)
    fail(rows[kMaxConditionsRows + 1].line, "expected at most " + std::to_string(kMaxConditionsRows) + " conditions");
  const MethodDescriptor& test = describe(config.stimulus.test.method);
  const std::string& level_key = config.levels.parameter;
  const std::vector<std::string>& header = rows.front().cells;
  const int header_line = rows.front().line;
  int variant_column = -1, level_column = -1;
  std::vector<const ParameterDescriptor*> parameters(header.size(), nullptr);
  std::set<std::string> seen;
  for (size_t column = 0; column < header.size(); ++column) {
    const std::string& key = header[column];
    if (key.empty())
      fail(header_line, "column " + std::to_string(column + 1) + ": expected a column name, got an empty cell");
    if (!seen.insert(key).second) fail(header_line, "column " + quoted_input(key) + " appears twice");
    if (key == "variant") variant_column = int(column);
    else if (!level_key.empty() && key == level_key) level_column = int(column);
    else if (!(parameters[column] = find_parameter(test, key, reading.legacy_keys)))
      fail(header_line, "column " + quoted_input(key) + ": expected variant" +
                            (level_key.empty() ? "" : ", " + level_key + " (the level)") +
                            " or a parameter of the test method \"" + std::string(test.name) + "\" (" +
                            parameter_keys(test) + ")");
  }
  if (!level_key.empty() && level_column < 0)
    fail(header_line, "expected a column \"" + level_key + "\" ([levels] parameter) holding each condition's level");
  const bool overrides =
      std::any_of(parameters.begin(), parameters.end(), [](const ParameterDescriptor* p) { return p; });
  if (variant_column < 0 && (overrides || level_column < 0))
    fail(header_line,
         "expected a column \"variant\" naming each condition's variant (without one, only the level column)");

  const ParameterDescriptor* level_parameter = level_column >= 0 ? find_parameter(test, level_key) : nullptr;
  // Rows, grouped by variant in order of first appearance.
  std::map<std::string, size_t> variant_index;
  std::vector<int> first_line;
  for (size_t r = 1; r < rows.size(); ++r) {
    const CsvRow& row = rows[r];
    if (row.cells.size() != header.size())
      fail(row.line, "expected " + std::to_string(header.size()) + " cells as the header has, got " +
                         std::to_string(row.cells.size()));
    const std::string variant_name = variant_column >= 0 ? row.cells[size_t(variant_column)] : std::string();
    if (variant_column >= 0 && !is_safe_name(variant_name))
      fail(row.line, "variant " + quoted_input(variant_name) + ": expected 1-64 letters, digits, '_', '-' or '.'");
    ParameterLayer layer;
    std::optional<double> level;
    for (size_t column = 0; column < header.size(); ++column) {
      const std::string& cell = row.cells[column];
      const ParameterDescriptor* parameter = int(column) == level_column ? level_parameter : parameters[column];
      if (!parameter) continue;
      const std::string where = "column " + quoted_input(header[column]) + ": ";
      if (cell.empty()) {
        if (int(column) == level_column) fail(row.line, where + "expected the condition's level, got an empty cell");
        continue;
      }
      double value = 0.0;
      if (parameter->type == ParameterType::choice) {
        const std::optional<double> index = parse_choice(*parameter, cell, reading.log_schema_version);
        if (!index)
          fail(row.line, where + "expected " + *check_parameter_value(*parameter, -1) + ", got " + quoted_input(cell));
        value = *index;
      } else {
        const std::optional<double> number = parse_finite_number(cell);
        if (!number) fail(row.line, where + "expected a number, got " + quoted_input(cell));
        value = *number;
      }
      if (const std::optional<std::string> expected = check_parameter_value(*parameter, value))
        fail(row.line, where + "expected " + *expected + ", got " + cell);  // as the file has it
      if (int(column) == level_column) level = value;
      else layer[std::string(parameter->key)] = value;
    }
    ParameterLayer level_layer;
    if (level) level_layer[level_key] = *level;
    if (const auto conflict =
            parameter_conflict(parameters_with(test.method, {&config.stimulus.test.parameters, &layer, &level_layer})))
      fail(row.line, conflict->expected);
    const auto [found, added] = variant_index.emplace(variant_name, config.stimulus.variants.size());
    if (added) {
      config.stimulus.variants.push_back(VariantConfig{variant_name, layer, {}});
      first_line.push_back(row.line);
    }
    VariantConfig& variant = config.stimulus.variants[found->second];
    if (variant.parameters != layer)
      fail(row.line, "variant \"" + variant_name + "\" sets other parameters than on line " +
                         std::to_string(first_line[found->second]) +
                         " (a variant's rows differ in level only; name another variant)");
    if (!level) {
      if (!added)
        fail(row.line, "variant \"" + variant_name + "\" is a condition already (line " +
                           std::to_string(first_line[found->second]) + ")");
      continue;
    }
    if (std::find(variant.levels.begin(), variant.levels.end(), *level) != variant.levels.end())
      fail(row.line, "the condition " + (variant_name.empty() ? "" : variant_name + " at ") + level_key + " = " +
                         format_number(*level, 6) + " appears twice");
    variant.levels.push_back(*level);
  }
  std::set<double> all_levels;
  for (VariantConfig& variant : config.stimulus.variants) {
    std::sort(variant.levels.begin(), variant.levels.end());
    all_levels.insert(variant.levels.begin(), variant.levels.end());
  }
  config.levels.values.assign(all_levels.begin(), all_levels.end());
  // Only the level column: a list of levels, not variants.
  if (variant_column < 0) config.stimulus.variants.clear();
}

}  // namespace fovlab::config_detail
