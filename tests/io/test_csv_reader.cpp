// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/csv_reader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

using ::testing::HasSubstr;

// Reads every row of `text`; returns the error message, or "no error".
std::string error_of(const std::string& text) {
  try {
    CsvReader reader = CsvReader::from_text("f.csv", text);
    CsvReader::Row row;
    while (reader.next(row)) {
    }
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(CsvReader, ReadsQuotedFieldsCrlfBomAndBlankLines) {
  CsvReader reader = CsvReader::from_text("f.csv", "\xEF\xBB\xBF" "a, b ,c\r\n\r\n\"x,1\", 2 ,\"say \"\"hi\"\"\"\r\n");
  CsvReader::Row row;
  ASSERT_TRUE(reader.next(row));
  EXPECT_EQ(row.line, 3);
  EXPECT_EQ(row.fields, (std::vector<std::string>{"x,1", "2", "say \"hi\""}));
  EXPECT_EQ(reader.column_index("a"), 0);
  EXPECT_EQ(reader.column_index("b"), 1);
  EXPECT_DOUBLE_EQ(reader.number(row, 1), 2.0);
  EXPECT_FALSE(reader.next(row));
}

TEST(CsvReader, NumbersMustBeFiniteDecimals) {
  CsvReader reader = CsvReader::from_text("f.csv", "a,b,c,d,e,f\n1e-3,+2,nan,inf,1x,1e999\n");
  CsvReader::Row row;
  ASSERT_TRUE(reader.next(row));
  EXPECT_DOUBLE_EQ(reader.number(row, 0), 1e-3);
  EXPECT_DOUBLE_EQ(reader.number(row, 1), 2.0);
  EXPECT_THROW(reader.number(row, 2), InputError);
  EXPECT_THROW(reader.number(row, 3), InputError);
  EXPECT_THROW(reader.number(row, 5), InputError);
  try {
    reader.number(row, 4);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "f.csv:2: column 'e': '1x' is not a number");
  }
}

TEST(CsvReader, RejectsMalformedFiles) {
  EXPECT_EQ(error_of(""), "f.csv: the file is empty (no header row)");
  EXPECT_EQ(error_of("\na,b\n"), "f.csv:1: the header row is empty");
  EXPECT_EQ(error_of("a,a\n1,2\n"), "f.csv:1: column 'a' appears twice");
  EXPECT_EQ(error_of("a,,b\n"), "f.csv:1: header column 2 has no name");
  EXPECT_EQ(error_of("a,b\n1,2\n3\n"), "f.csv:3: expected 2 fields as in the header, found 1");
  EXPECT_EQ(error_of("a,b\n\"1,2\n"), "f.csv:2: unterminated quoted field");
  EXPECT_EQ(error_of("a,b\n\"1\"x,2\n"), "f.csv:2: unexpected text after a quoted field");
  EXPECT_EQ(error_of("a,b\n1,2\n\n  \n3,4"), "no error");
}

TEST(CsvReader, MissingFileIsAnInputError) {
  EXPECT_THROW(CsvReader::open("/nonexistent/file.csv"), InputError);
}

}  // namespace
}  // namespace stgf
