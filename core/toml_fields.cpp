#include "core/toml_fields.h"

#include <cmath>

#include "core/input_error.h"
#include "core/toml_guard.h"

namespace fovlab {
namespace {

std::string type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "a date or time";
  }
}

}  // namespace

TomlFields::TomlFields(const toml::table& table, std::string path, std::string prefix)
    : table_(table), path_(std::move(path)), prefix_(std::move(prefix)) {}

std::string TomlFields::name_of(const std::string& key) const {
  return unshield_toml_hazards(prefix_.empty() ? key : prefix_ + "." + key);
}

int TomlFields::line_of(const toml::node* node) const {
  return node ? static_cast<int>(node->source().begin.line) : static_cast<int>(table_.source().begin.line);
}

void TomlFields::fail(const std::string& key, const std::string& expected) const {
  const toml::node* node = table_.get(key);
  const int line = line_of(node);
  std::string where = path_;
  if (line > 0) where += ":" + std::to_string(line);
  const std::string name = key.empty() ? (prefix_.empty() ? "config" : prefix_) : name_of(key);
  throw InputError(where + ": " + name + ": " + expected);
}

const toml::node* TomlFields::find(const std::string& key) const {
  read_.insert(key);
  return table_.get(key);
}

const toml::node& TomlFields::node(const std::string& key) const {
  const toml::node* found = find(key);
  if (!found) fail(key, "missing (required)");
  return *found;
}

bool TomlFields::has(const std::string& key) const { return table_.contains(key); }

std::string TomlFields::string(const std::string& key) const {
  const toml::node& found = node(key);
  if (!found.is_string()) fail(key, "expected a string, got " + type_name(found));
  return unshield_toml_hazards(found.value<std::string>().value());
}

std::string TomlFields::string(const std::string& key, const std::string& fallback) const {
  return has(key) ? string(key) : (read_.insert(key), fallback);
}

double TomlFields::number(const std::string& key) const {
  const toml::node& found = node(key);
  if (!found.is_number()) fail(key, "expected a number, got " + type_name(found));
  const double value = found.value<double>().value();
  if (!std::isfinite(value)) fail(key, "expected a finite number");
  return value;
}

double TomlFields::number(const std::string& key, double fallback) const {
  return has(key) ? number(key) : (read_.insert(key), fallback);
}

int64_t TomlFields::integer(const std::string& key) const {
  const toml::node& found = node(key);
  if (!found.is_integer()) fail(key, "expected an integer, got " + type_name(found));
  return found.value<int64_t>().value();
}

int64_t TomlFields::integer(const std::string& key, int64_t fallback) const {
  return has(key) ? integer(key) : (read_.insert(key), fallback);
}

bool TomlFields::boolean(const std::string& key, bool fallback) const {
  if (!has(key)) return read_.insert(key), fallback;
  const toml::node& found = node(key);
  if (!found.is_boolean()) fail(key, "expected true or false, got " + type_name(found));
  return found.value<bool>().value();
}

std::vector<double> TomlFields::numbers(const std::string& key) const {
  const toml::node& found = node(key);
  const toml::array* array = found.as_array();
  if (!array || array->empty()) fail(key, "expected a non-empty array of numbers");
  std::vector<double> values;
  for (const toml::node& element : *array) {
    if (!element.is_number()) fail(key, "expected a non-empty array of numbers, found " + type_name(element));
    const double value = element.value<double>().value();
    if (!std::isfinite(value)) fail(key, "expected finite numbers");
    values.push_back(value);
  }
  return values;
}

std::vector<std::string> TomlFields::strings(const std::string& key) const {
  const toml::node& found = node(key);
  const toml::array* array = found.as_array();
  if (!array || array->empty()) fail(key, "expected a non-empty array of strings");
  std::vector<std::string> values;
  for (const toml::node& element : *array) {
    if (!element.is_string()) fail(key, "expected a non-empty array of strings, found " + type_name(element));
    values.push_back(unshield_toml_hazards(element.value<std::string>().value()));
  }
  return values;
}

TomlFields TomlFields::table(const std::string& key) const {
  const toml::node& found = node(key);
  const toml::table* sub = found.as_table();
  if (!sub) fail(key, "expected a table ([" + name_of(key) + "]), got " + type_name(found));
  return TomlFields(*sub, path_, name_of(key));
}

const toml::table* TomlFields::optional_table(const std::string& key) const {
  const toml::node* found = find(key);
  if (!found) return nullptr;
  if (!found->is_table()) fail(key, "expected a table ([" + name_of(key) + "]), got " + type_name(*found));
  return found->as_table();
}

std::vector<TomlFields> TomlFields::tables(const std::string& key) const {
  const toml::node& found = node(key);
  const toml::array* array = found.as_array();
  if (!array || array->empty() || !array->is_array_of_tables())
    fail(key, "expected one or more [[" + name_of(key) + "]] tables");
  std::vector<TomlFields> result;
  for (size_t i = 0; i < array->size(); ++i)
    result.emplace_back(*array->get(i)->as_table(), path_, name_of(key) + "[" + std::to_string(i + 1) + "]");
  return result;
}

void TomlFields::finish() const {
  for (auto&& [key, value] : table_) {
    const std::string name(key.str());
    if (!read_.count(name)) {
      const int line = static_cast<int>(value.source().begin.line);
      throw InputError(path_ + (line > 0 ? ":" + std::to_string(line) : "") + ": " + name_of(name) +
                       ": unknown key (see docs/config.md for the keys of this table)");
    }
  }
}

}  // namespace fovlab
