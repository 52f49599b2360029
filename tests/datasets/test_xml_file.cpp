// SPDX-License-Identifier: Apache-2.0
// The XML source files of this layer (datasets/xml_file.hpp): line numbers, attribute numbers, and
// InputError at the line of the element concerned.

#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "stgf/datasets/xml_file.hpp"
#include "stgf/io/input_error.hpp"
#include "support/input_errors.hpp"
#include "support/scratch_directory.hpp"

namespace stgf {
namespace {

using testing::expect_input_error;
using testing::ScratchDirectory;

TEST(LineIndex, LinesByByteOffset) {
  const LineIndex lines("ab\ncd\n\nef");
  EXPECT_EQ(lines.line_at(-1), 0);
  EXPECT_EQ(lines.line_at(0), 1);
  EXPECT_EQ(lines.line_at(2), 1);  // the '\n' ends line 1
  EXPECT_EQ(lines.line_at(3), 2);
  EXPECT_EQ(lines.line_at(6), 3);
  EXPECT_EQ(lines.line_at(7), 4);
}

TEST(XmlFile, AttributeNumbersAllowBlanksAndAPlus) {
  EXPECT_EQ(parse_attribute_number(" +4.5e-3\n"), 4.5e-3);
  for (const std::string_view bad : {"", " ", "abc", "nan", "inf", "1 2"}) {
    EXPECT_FALSE(parse_attribute_number(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(XmlFile, ReadsNumbersAndReportsTheElementsLine) {
  const ScratchDirectory scratch;
  const std::string path = scratch.write(
      "good.xml", "<?xml version=\"1.0\"?>\n<Camera>\n  <Size width=\" 768 \" height=\"x\"/>\n</Camera>\n");
  const XmlFile file(path, "Camera");
  EXPECT_EQ(file.path(), path);
  const pugi::xml_node size = file.top().child("Size");
  EXPECT_EQ(file.line(file.top()), 2);
  EXPECT_EQ(file.line(size), 3);
  EXPECT_EQ(file.number(size, "width"), 768.0);
  EXPECT_EQ(expect_input_error([&] { file.number(size, "height"); }, path, 3),
            path + ":3: <Size> attribute height=\"x\" is not a finite number");
  EXPECT_EQ(expect_input_error([&] { file.number(size, "depth"); }, path, 3),
            path + ":3: <Size> has no attribute depth");
  EXPECT_EQ(expect_input_error([&] { file.fail(file.top(), "bad camera"); }, path, 2),
            path + ":2: bad camera");
}

TEST(XmlFile, BadFilesNameTheFileAndLine) {
  const ScratchDirectory scratch;
  const std::string broken = scratch.write("broken.xml", "<Camera>\n  <Size>\n</Camera>\n");
  const std::string message = expect_input_error([&] { XmlFile(broken, "Camera"); }, broken, 3);
  EXPECT_NE(message.find("not well-formed XML"), std::string::npos) << message;

  const std::string other = scratch.write("other.xml", "<dataset/>\n");
  EXPECT_EQ(expect_input_error([&] { XmlFile(other, "Camera"); }, other, 0),
            other + ": no <Camera> element at the top level");

  const std::string absent = scratch / "absent.xml";
  EXPECT_EQ(expect_input_error([&] { XmlFile(absent, "Camera"); }, absent, 0),
            absent + ": cannot open the file");
}

}  // namespace
}  // namespace stgf
