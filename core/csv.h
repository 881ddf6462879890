#pragma once
// CSV as RFC 4180 writes it, so pandas.read_csv and R's read.csv take it as is: cells separated by
// commas, a line ending in "\n", and a cell holding a comma, a double quote, CR or LF enclosed in
// double quotes with its quotes doubled (park, "north" -> "park, ""north""").
#include <string>
#include <vector>

namespace fovlab {

inline std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// One line: every cell quoted as needed (numbers never are).
inline std::string csv_line(const std::vector<std::string>& cells) {
  std::string line;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (i) line += ',';
    line += csv_cell(cells[i]);
  }
  return line + "\n";
}

}  // namespace fovlab
