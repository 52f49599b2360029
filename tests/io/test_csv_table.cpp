#include "stgf/io/csv_table.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

using ::testing::HasSubstr;

std::string error_of(std::string_view text) {
  try {
    CsvTable::parse("f.csv", text);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(CsvTable, ReadsQuotedFieldsCrlfBomAndBlankLines) {
  const CsvTable table = CsvTable::parse("f.csv", "\xEF\xBB\xBF" "a, b ,c\r\n\r\n\"x,1\", 2 ,\"say \"\"hi\"\"\"\r\n");
  ASSERT_EQ(table.rows().size(), 1u);
  EXPECT_EQ(table.rows()[0].line, 3);
  EXPECT_EQ(table.rows()[0].fields, (std::vector<std::string>{"x,1", "2", "say \"hi\""}));
  EXPECT_EQ(table.column_index("b"), 1);
  EXPECT_DOUBLE_EQ(table.number(table.rows()[0], 1), 2.0);
}

TEST(CsvTable, NumbersMustBeFiniteDecimals) {
  const CsvTable table = CsvTable::parse("f.csv", "a,b,c,d,e\n1e-3,+2,nan,inf,1x\n");
  const auto& row = table.rows()[0];
  EXPECT_DOUBLE_EQ(table.number(row, 0), 1e-3);
  EXPECT_DOUBLE_EQ(table.number(row, 1), 2.0);
  EXPECT_THROW(table.number(row, 2), InputError);
  EXPECT_THROW(table.number(row, 3), InputError);
  try {
    table.number(row, 4);
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "f.csv:2: column 'e': '1x' is not a number");
  }
}

TEST(CsvTable, RejectsMalformedFiles) {
  EXPECT_THAT(error_of(""), HasSubstr("f.csv: the file is empty"));
  EXPECT_THAT(error_of("a,a\n1,2\n"), HasSubstr("f.csv:1: column 'a' appears twice"));
  EXPECT_THAT(error_of("a,b\n1,2\n3\n"), HasSubstr("f.csv:3: expected 2 fields as in the header, found 1"));
  EXPECT_THAT(error_of("a,b\n\"1,2\n"), HasSubstr("f.csv:2: unterminated quoted field"));
}

TEST(CsvTable, MissingFileIsAnInputError) {
  EXPECT_THROW(CsvTable::read("/nonexistent/file.csv"), InputError);
}

}  // namespace
}  // namespace stgf
