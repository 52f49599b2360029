// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/csv_reader.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "stgf/io/input_bounds.hpp"
#include "stgf/io/input_error.hpp"

namespace stgf {
namespace {

std::string_view trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

// Splits one line into `fields`, reusing their storage; quoted fields may hold commas and "".
void split_fields(const std::string& path, int line, std::string_view text, std::vector<std::string>& fields) {
  std::size_t count = 0;
  std::size_t i = 0;
  while (true) {
    if (count == fields.size()) fields.emplace_back();
    std::string& field = fields[count++];
    field.clear();
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    if (i < text.size() && text[i] == '"') {
      ++i;
      while (true) {
        if (i >= text.size()) throw InputError(path, line, "unterminated quoted field");
        if (text[i] == '"') {
          if (i + 1 < text.size() && text[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        field += text[i++];
      }
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
      if (i < text.size() && text[i] != ',') throw InputError(path, line, "unexpected text after a quoted field");
    } else {
      const auto comma = text.find(',', i);
      const auto end = comma == std::string_view::npos ? text.size() : comma;
      field.assign(trimmed(text.substr(i, end - i)));
      i = end;
    }
    if (i >= text.size()) break;
    ++i;  // the comma
  }
  fields.resize(count);
}

}  // namespace

CsvReader::CsvReader(std::string path, std::unique_ptr<std::istream> input)
    : path_(std::move(path)), input_(std::move(input)) {}

CsvReader CsvReader::open(const std::string& path) {
  auto file = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*file) throw InputError(path, 0, "cannot open the file");
  CsvReader reader(path, std::move(file));
  reader.read_header();
  return reader;
}

CsvReader CsvReader::from_text(const std::string& path, std::string text) {
  CsvReader reader(path, std::make_unique<std::istringstream>(std::move(text)));
  reader.read_header();
  return reader;
}

bool CsvReader::next_line(std::string& line) {
  while (std::getline(*input_, line)) {
    ++line_number_;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_number_ == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    if (!trimmed(line).empty()) return true;
    if (line_number_ == 1) throw InputError(path_, 1, "the header row is empty");
  }
  if (input_->bad()) throw InputError(path_, line_number_, "cannot read the file");
  return false;
}

void CsvReader::read_header() {
  if (!next_line(line_)) throw InputError(path_, 0, "the file is empty (no header row)");
  split_fields(path_, line_number_, line_, header_);
  for (std::size_t c = 0; c < header_.size(); ++c) {
    if (header_[c].empty()) {
      throw InputError(path_, line_number_, "header column " + std::to_string(c + 1) + " has no name");
    }
    for (std::size_t d = 0; d < c; ++d) {
      if (header_[d] == header_[c]) throw InputError(path_, line_number_, "column '" + header_[c] + "' appears twice");
    }
  }
}

bool CsvReader::next(Row& row) {
  if (!next_line(line_)) return false;
  row.line = line_number_;
  split_fields(path_, line_number_, line_, row.fields);
  if (row.fields.size() != header_.size()) {
    throw InputError(path_, line_number_,
                     "expected " + std::to_string(header_.size()) + " fields as in the header, found " +
                         std::to_string(row.fields.size()));
  }
  return true;
}

int CsvReader::column_index(std::string_view name) const {
  for (std::size_t c = 0; c < header_.size(); ++c) {
    if (header_[c] == name) return static_cast<int>(c);
  }
  return -1;
}

int CsvReader::require_column(std::string_view name) const {
  const int index = column_index(name);
  if (index < 0) throw InputError(path_, 1, "missing column '" + std::string(name) + "'");
  return index;
}

const std::string& CsvReader::text(const Row& row, int column) const {
  const std::string& field = row.fields[static_cast<std::size_t>(column)];
  if (field.empty()) fail(row, "column " + quoted_excerpt(header_[static_cast<std::size_t>(column)]) + " is empty");
  return field;
}

double CsvReader::number(const Row& row, int column) const {
  const std::string& field = row.fields[static_cast<std::size_t>(column)];
  const std::string& name = header_[static_cast<std::size_t>(column)];
  if (field.empty()) fail(row, "column " + quoted_excerpt(name) + " is empty");
  const char* begin = field.data();
  if (*begin == '+') ++begin;  // from_chars does not take a leading plus
  double value = 0.0;
  const auto [end, error] = std::from_chars(begin, field.data() + field.size(), value);
  // The message is built only on failure: this runs for every number of every row.
  if (error == std::errc::result_out_of_range) fail(row, column_and_field(row, column) + " is out of range");
  if (error != std::errc() || end != field.data() + field.size()) {
    fail(row, column_and_field(row, column) + " is not a number");
  }
  if (!std::isfinite(value)) fail(row, column_and_field(row, column) + " is not finite");
  return value;
}

double CsvReader::bounded_number(const Row& row, int column, double max_abs, const char* what) const {
  const double value = number(row, column);
  if (std::abs(value) > max_abs) {
    fail(row, column_and_field(row, column) + " is outside ±" +
                  fmt::format("{:g}", max_abs) + " (stgf's bound on " + what + ")");
  }
  return value;
}

Eigen::Vector3d CsvReader::vector3(const Row& row, const int (&columns)[3]) const {
  const char* what = "coordinates (m)";
  return {bounded_number(row, columns[0], kMaxAbsCoordinate, what),
          bounded_number(row, columns[1], kMaxAbsCoordinate, what),
          bounded_number(row, columns[2], kMaxAbsCoordinate, what)};
}

double CsvReader::time(const Row& row, int column) const { return bounded_number(row, column, kMaxAbsTime, "times (s)"); }

Eigen::Matrix3d CsvReader::symmetric3(const Row& row, const int (&columns)[6]) const {
  const double xx = number(row, columns[0]), xy = number(row, columns[1]), xz = number(row, columns[2]);
  const double yy = number(row, columns[3]), yz = number(row, columns[4]), zz = number(row, columns[5]);
  for (const auto& [variance, column] : {std::pair{xx, columns[0]}, std::pair{yy, columns[3]}, std::pair{zz, columns[5]}}) {
    if (variance <= 0.0) {
      fail(row, "covariance is not positive definite (column " +
                    quoted_excerpt(header_[static_cast<std::size_t>(column)]) + " is " +
                    quoted_excerpt(row.fields[static_cast<std::size_t>(column)]) + ")");
    }
    if (!(variance >= kMinVariance && variance <= kMaxVariance)) {
      fail(row, column_and_field(row, column) + " is outside [1e-12, 1e12] m² (stgf's bound on a variance)");
    }
  }
  Eigen::Matrix3d matrix;
  matrix << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  return matrix;
}

void CsvReader::fail(const Row& row, const std::string& what) const { throw InputError(path_, row.line, what); }

std::string CsvReader::column_and_field(const Row& row, int column) const {
  const auto k = static_cast<std::size_t>(column);
  return "column " + quoted_excerpt(header_[k]) + ": " + quoted_excerpt(row.fields[k]);
}

}  // namespace stgf
