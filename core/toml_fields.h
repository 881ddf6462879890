#pragma once
// Reads fields of a TOML table with the error messages every fovlab config uses:
// "path:LINE: key: what was expected". It remembers which keys were read, so finish() can reject
// the keys nobody asked for (a misspelt key is an error, never silently ignored).
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace fovlab {

class TomlFields {
 public:
  // `prefix` is the dotted name of this table ("display", "block[2]"), "" for the root.
  TomlFields(const toml::table& table, std::string path, std::string prefix);

  bool has(const std::string& key) const;
  std::string string(const std::string& key) const;  // required
  std::string string(const std::string& key, const std::string& fallback) const;
  double number(const std::string& key) const;  // integer or float, finite
  double number(const std::string& key, double fallback) const;
  int64_t integer(const std::string& key) const;
  int64_t integer(const std::string& key, int64_t fallback) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::vector<double> numbers(const std::string& key) const;       // array of numbers, not empty
  std::vector<std::string> strings(const std::string& key) const;  // array of strings, not empty
  TomlFields table(const std::string& key) const;                  // required sub-table
  const toml::table* optional_table(const std::string& key) const;
  std::vector<TomlFields> tables(const std::string& key) const;  // array of tables, not empty
  const toml::table& raw() const { return table_; }
  const std::string& path() const { return path_; }

  // Throws for the first key that was never read.
  void finish() const;

  // An error about key (its line when present, else the table's), or about the table itself.
  [[noreturn]] void fail(const std::string& key, const std::string& expected) const;
  std::string name_of(const std::string& key) const;  // "display.width_px"

 private:
  const toml::node& node(const std::string& key) const;  // required; marks read
  const toml::node* find(const std::string& key) const;  // optional; marks read
  int line_of(const toml::node* node) const;

  const toml::table& table_;
  std::string path_;
  std::string prefix_;
  mutable std::set<std::string> read_;
};

}  // namespace fovlab
