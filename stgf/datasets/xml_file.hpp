// SPDX-License-Identifier: Apache-2.0
#pragma once
// An XML source file of this layer (Tsai calibrations, PETS 2009 annotations): read whole, parsed
// with pugixml, and every problem reported as InputError (stgf/io/input_error.hpp) naming the file
// and the line of the element concerned. For tsai_camera.cpp and pets2009.cpp; pugixml is private to
// this layer, so this header is not for its users.

#include <cstddef>
#include <optional>
#include <pugixml.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace stgf {

// Line numbers of a text by byte offset (pugixml reports byte offsets): the offsets of its line
// breaks, found once, then a binary search per query.
class LineIndex {
 public:
  explicit LineIndex(std::string_view text);
  // The 1-based line on which byte `offset` lies; 0 when the offset is unknown (negative).
  int line_at(std::ptrdiff_t offset) const;

 private:
  std::vector<std::ptrdiff_t> line_breaks_;  // offsets of the '\n' characters, ascending
};

// The number an attribute's value spells, when all of it is one finite decimal number (blanks around
// it and a leading '+' allowed).
std::optional<double> parse_attribute_number(std::string_view value);

class XmlFile {
 public:
  // Reads and parses `path` and finds its top-level element named `top`. InputError when the file
  // cannot be read (line 0), is not well-formed XML ("not well-formed XML: …" at the line of the
  // error) or has no such element ("no <top> element at the top level", line 0).
  XmlFile(const std::string& path, const char* top);

  const std::string& path() const { return path_; }
  const pugi::xml_node& top() const { return top_; }
  // The line on which `node` starts.
  int line(const pugi::xml_node& node) const { return lines_.line_at(node.offset_debug()); }

  // Throws InputError(path, line(node), what).
  [[noreturn]] void fail(const pugi::xml_node& node, const std::string& what) const;

  // The attribute `name` of `element` as a finite number (parse_attribute_number); fails with
  // "<element> has no attribute name" or "<element> attribute name="…" is not a finite number".
  double number(const pugi::xml_node& element, const char* name) const;

 private:
  XmlFile(const std::string& path, const std::string& text, const char* top);

  std::string path_;
  LineIndex lines_;
  pugi::xml_document document_;
  pugi::xml_node top_;
};

}  // namespace stgf
