#pragma once
// CSV as RFC 4180 writes it, so pandas.read_csv and R's read.csv take it as is: cells separated by
// commas, a line ending in "\n", and a cell holding a comma, a double quote, CR or LF enclosed in
// double quotes with its quotes doubled (park, "north" -> "park, ""north""").
//
// And read back (read_csv_rows), as a spreadsheet or pandas writes it.
#include <string>
#include <string_view>
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

// One record of a CSV text: its cells and the line it starts on (1-based).
struct CsvRow {
  int line = 0;
  std::vector<std::string> cells;
};

// The records of an RFC 4180 text: cells separated by commas; a cell in double quotes may hold
// commas, line breaks and doubled quotes. Lines end in LF, CRLF or a lone CR; a UTF-8 byte-order
// mark at the start and blank lines (also lines of empty cells only) are skipped; spaces are kept
// as written. Throws InputError
// "name:LINE: ..." for a quote that is never closed or text after a closing quote.
std::vector<CsvRow> read_csv_rows(std::string_view text, const std::string& name);

}  // namespace fovlab
