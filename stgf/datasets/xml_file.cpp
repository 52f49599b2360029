// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/xml_file.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "stgf/datasets/text_input.hpp"
#include "stgf/io/input_error.hpp"

namespace stgf {

LineIndex::LineIndex(std::string_view text) {
  for (std::size_t at = text.find('\n'); at != std::string_view::npos; at = text.find('\n', at + 1)) {
    line_breaks_.push_back(static_cast<std::ptrdiff_t>(at));
  }
}

int LineIndex::line_at(std::ptrdiff_t offset) const {
  if (offset < 0) return 0;
  // Line = 1 + the number of line breaks before the offset.
  return 1 + static_cast<int>(std::lower_bound(line_breaks_.begin(), line_breaks_.end(), offset) -
                              line_breaks_.begin());
}

std::optional<double> parse_attribute_number(std::string_view value) {
  return parse_finite_number(trim_blanks(value));
}

XmlFile::XmlFile(const std::string& path, const char* top) : XmlFile(path, read_whole_file(path), top) {}

XmlFile::XmlFile(const std::string& path, const std::string& text, const char* top)
    : path_(path), lines_(text) {
  const pugi::xml_parse_result parsed = document_.load_buffer(text.data(), text.size());
  if (!parsed) {
    throw InputError(path_, lines_.line_at(parsed.offset),
                     fmt::format("not well-formed XML: {}", parsed.description()));
  }
  top_ = document_.child(top);
  if (!top_) throw InputError(path_, 0, fmt::format("no <{}> element at the top level", top));
}

void XmlFile::fail(const pugi::xml_node& node, const std::string& what) const {
  throw InputError(path_, line(node), what);
}

double XmlFile::number(const pugi::xml_node& element, const char* name) const {
  const pugi::xml_attribute attribute = element.attribute(name);
  if (!attribute) fail(element, fmt::format("<{}> has no attribute {}", element.name(), name));
  const std::optional<double> value = parse_attribute_number(attribute.value());
  if (!value) {
    fail(element, fmt::format("<{}> attribute {}=\"{}\" is not a finite number", element.name(), name,
                              attribute.value()));
  }
  return *value;
}

}  // namespace stgf
