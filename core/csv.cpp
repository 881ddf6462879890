#include "core/csv.h"

#include <algorithm>

#include "core/input_error.h"

namespace fovlab {

std::vector<CsvRow> read_csv_rows(std::string_view text, const std::string& name) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  std::vector<CsvRow> rows;
  CsvRow row;
  std::string cell;
  int line = 1;
  size_t i = 0;
  const auto fail = [&](const std::string& what) {
    throw InputError(name + ":" + std::to_string(line) + ": " + what +
                     " (expected CSV: cells separated by commas, "
                     "a cell with a comma, quote or line break in double quotes)");
  };
  const auto end_row = [&] {
    row.cells.push_back(std::move(cell));
    cell.clear();
    // A line of empty cells (",,," as spreadsheets leave below a table) is blank too.
    const bool blank = std::all_of(row.cells.begin(), row.cells.end(), [](const std::string& c) { return c.empty(); });
    if (!blank) rows.push_back(std::move(row));
    row = CsvRow{};
  };
  row.line = line;
  while (i < text.size()) {
    const char c = text[i];
    if (c == '"' && cell.empty()) {
      // A quoted cell: up to the closing quote ("" is a quote), then a comma or the line's end.
      const int opened = line;
      for (++i;; ++i) {
        if (i >= text.size()) {
          line = opened;
          fail("a quoted cell is never closed");
        }
        if (text[i] == '"') {
          if (i + 1 < text.size() && text[i + 1] == '"') {
            cell += '"';
            ++i;
            continue;
          }
          ++i;
          break;
        }
        if (text[i] == '\n') ++line;
        cell += text[i];
      }
      if (i < text.size() && text[i] != ',' && text[i] != '\n' && text[i] != '\r')
        fail("text after a quoted cell's closing quote");
      continue;  // the comma or line end is the loop's
    }
    if (c == ',') {
      row.cells.push_back(std::move(cell));
      cell.clear();
      ++i;
      continue;
    }
    if (c == '\n' || c == '\r') {  // LF, CRLF, or a lone CR (old Mac spreadsheets)
      end_row();
      i += c == '\r' && i + 1 < text.size() && text[i + 1] == '\n' ? 2 : 1;
      ++line;
      row.line = line;
      continue;
    }
    cell += c;
    ++i;
  }
  end_row();  // the last line, when it has no line end (blank: nothing)
  return rows;
}

}  // namespace fovlab
