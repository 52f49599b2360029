// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/text_input.hpp"

#include <charconv>
#include <cmath>
#include <sstream>
#include <system_error>

#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

// `text` without one leading '+' (std::from_chars does not take a sign other than '-').
std::string_view without_plus(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  return text;
}

// All of `text` as one Number by std::from_chars; nullopt otherwise.
template <typename Number>
std::optional<Number> parse_whole(std::string_view text) {
  Number value{};
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value);
  if (error != std::errc() || stop != end) return std::nullopt;
  return value;
}

}  // namespace

std::string read_whole_file(const std::string& path) {
  std::ifstream input(path, std::ios::binary);
  if (!input) throw InputError(path, 0, "cannot open the file");
  std::ostringstream text;
  text << input.rdbuf();
  if (input.bad()) throw InputError(path, 0, "cannot read the file");
  return text.str();
}

std::ifstream open_text_file(const std::string& path) {
  std::ifstream input(path);
  if (!input) throw InputError(path, 0, "cannot open the file");
  return input;
}

std::vector<std::string_view> split_fields(std::string_view line, std::string_view separators) {
  const auto is_separator = [&](char c) { return separators.find(c) != std::string_view::npos; };
  std::vector<std::string_view> fields;
  std::size_t position = 0;
  while (position < line.size()) {
    while (position < line.size() && is_separator(line[position])) ++position;
    const std::size_t start = position;
    while (position < line.size() && !is_separator(line[position])) ++position;
    if (position > start) fields.push_back(line.substr(start, position - start));
  }
  return fields;
}

std::string_view trim_blanks(std::string_view text) {
  const auto is_blank = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (!text.empty() && is_blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_blank(text.back())) text.remove_suffix(1);
  return text;
}

std::optional<double> parse_number(std::string_view text) { return parse_whole<double>(text); }

std::optional<double> parse_finite_number(std::string_view text) {
  const std::optional<double> value = parse_number(without_plus(text));
  if (!value || !std::isfinite(*value)) return std::nullopt;
  return value;
}

std::optional<int> parse_integer(std::string_view text) { return parse_whole<int>(without_plus(text)); }

}  // namespace stgf
