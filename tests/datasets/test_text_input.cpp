// SPDX-License-Identifier: Apache-2.0
// The text pieces shared by the source-data readers (datasets/text_input.hpp): fields, numbers and
// files, with the exact rules each reader relies on.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "stgf/datasets/text_input.hpp"
#include "stgf/io/input_error.hpp"
#include "support/input_errors.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

using testing::expect_input_error;
using testing::ScratchDirectory;

using Fields = std::vector<std::string_view>;

TEST(TextInput, SplitFieldsAtRunsOfSeparators) {
  EXPECT_EQ(split_fields("  0 3\tCar  -1.5 ", " \t"), (Fields{"0", "3", "Car", "-1.5"}));
  EXPECT_EQ(split_fields(" \t ", " \t"), Fields{});
  EXPECT_EQ(split_fields("", " \t"), Fields{});
  // Only the given separators separate: '\r' is part of a field unless it is one of them.
  EXPECT_EQ(split_fields("1 2\r", " \t"), (Fields{"1", "2\r"}));
  EXPECT_EQ(split_fields("1 2\r", " \t\r"), (Fields{"1", "2"}));
}

TEST(TextInput, TrimBlanks) {
  EXPECT_EQ(trim_blanks(" \t1.5\r\n"), "1.5");
  EXPECT_EQ(trim_blanks("a b"), "a b");
  EXPECT_EQ(trim_blanks(" \n "), "");
}

TEST(TextInput, ParseNumberTakesAllOfTheTextAsFromCharsReadsIt) {
  EXPECT_EQ(parse_number("-1.25e2"), -125.0);
  EXPECT_EQ(parse_number("780.0"), 780.0);
  EXPECT_TRUE(std::isinf(*parse_number("inf")));
  EXPECT_TRUE(std::isnan(*parse_number("nan")));
  for (const std::string_view bad : {"", "+1", " 1", "1 ", "1x", "x", "1e999"}) {
    EXPECT_FALSE(parse_number(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(TextInput, ParseFiniteNumberAllowsAPlusAndNothingInfinite) {
  EXPECT_EQ(parse_finite_number("+1.5"), 1.5);
  EXPECT_EQ(parse_finite_number("-0.003"), -0.003);
  for (const std::string_view bad : {"", "+", "++1", " 1", "inf", "-inf", "nan", "1e999", "1,5"}) {
    EXPECT_FALSE(parse_finite_number(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(TextInput, ParseIntegerAllowsAPlusAndNothingElse) {
  EXPECT_EQ(parse_integer("+7"), 7);
  EXPECT_EQ(parse_integer("-12"), -12);
  for (const std::string_view bad : {"", "7.0", "1e3", " 7", "99999999999"}) {
    EXPECT_FALSE(parse_integer(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(TextInput, FilesAreReadWholeOrNameTheFile) {
  const ScratchDirectory scratch;
  const std::string path = scratch.write("bytes.txt", std::string("a\r\nb\0c", 6));
  EXPECT_EQ(read_whole_file(path), std::string("a\r\nb\0c", 6));
  std::ifstream text = open_text_file(path);
  std::string first;
  std::getline(text, first);
  EXPECT_EQ(first, "a\r");

  const std::string absent = scratch / "absent.txt";
  EXPECT_EQ(expect_input_error([&] { read_whole_file(absent); }, absent, 0),
            absent + ": cannot open the file");
  EXPECT_EQ(expect_input_error([&] { open_text_file(absent); }, absent, 0),
            absent + ": cannot open the file");
}

}  // namespace
}  // namespace stgf
