// Tests of core/csv.h's reader: RFC 4180 as spreadsheets and pandas write it, and one-line errors.
#include <gtest/gtest.h>

#include "core/csv.h"
#include "core/input_error.h"

namespace fovlab {
namespace {

std::vector<std::vector<std::string>> cells_of(const std::string& text) {
  std::vector<std::vector<std::string>> cells;
  for (const CsvRow& row : read_csv_rows(text, "c.csv")) cells.push_back(row.cells);
  return cells;
}

std::string error_of(const std::string& text) {
  try {
    read_csv_rows(text, "c.csv");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(CsvReader, ReadsQuotedCellsLineEndsAndBlankLines) {
  using Rows = std::vector<std::vector<std::string>>;
  EXPECT_EQ(cells_of("a,b\n1,2\n"), (Rows{{"a", "b"}, {"1", "2"}}));
  EXPECT_EQ(cells_of("\xEF\xBB\xBF"
                     "a,b\r\n1,2"),
            (Rows{{"a", "b"}, {"1", "2"}}));  // BOM, CRLF, no last line end
  EXPECT_EQ(cells_of("a\n\n\nb\n"), (Rows{{"a"}, {"b"}}));
  EXPECT_EQ(cells_of("\"park, \"\"north\"\"\",x\n"), (Rows{{"park, \"north\"", "x"}}));
  EXPECT_EQ(cells_of("\"two\nlines\",y\nz,\n"), (Rows{{"two\nlines", "y"}, {"z", ""}}));
  EXPECT_EQ(cells_of("x,\"\",\n"), (Rows{{"x", "", ""}}));
  EXPECT_EQ(cells_of(" a , b \n"), (Rows{{" a ", " b "}}));                        // spaces are kept
  EXPECT_EQ(cells_of("a,b\r1,2\r"), (Rows{{"a", "b"}, {"1", "2"}}));               // lone CRs (old Mac spreadsheets)
  EXPECT_EQ(cells_of("a,b\n1,\"2\"\r\n,,\n,\n"), (Rows{{"a", "b"}, {"1", "2"}}));  // rows of empty cells are blank
  // The line a record starts on, for messages (the quoted line break counts).
  const std::vector<CsvRow> rows = read_csv_rows("h\n\"x\ny\"\n\nz\n", "c.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].line, 1);
  EXPECT_EQ(rows[1].line, 2);
  EXPECT_EQ(rows[2].line, 5);
}

TEST(CsvReader, AnUnclosedQuoteOrTextAfterOneIsAnErrorNamingTheLine) {
  EXPECT_EQ(error_of("a,b\n1,\"open\n2,3\n").rfind("c.csv:2: a quoted cell is never closed", 0), 0u)
      << error_of("a,b\n1,\"open\n2,3\n");
  EXPECT_EQ(error_of("a\n\"x\"y\n").rfind("c.csv:2: text after a quoted cell's closing quote", 0), 0u);
}

}  // namespace
}  // namespace fovlab
