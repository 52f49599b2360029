// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/record_columns.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

#include "stgf/core/records.hpp"
#include "stgf/io/input_error.hpp"

namespace stgf::detail {

const char* const kGaussianHeader = "x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz";

KeyColumns require_key_columns(const CsvReader& reader, bool with_view) {
  KeyColumns columns;
  columns.scene = reader.require_column("scene");
  columns.time = reader.require_column("t");
  if (with_view) columns.view = reader.require_column("view");
  columns.object = reader.require_column("object");
  return columns;
}

void require_position_columns(const CsvReader& reader, int (&columns)[3]) {
  columns[0] = reader.require_column("x");
  columns[1] = reader.require_column("y");
  columns[2] = reader.require_column("z");
}

GaussianColumns require_gaussian_columns(const CsvReader& reader) {
  GaussianColumns columns{};
  require_position_columns(reader, columns.mean);
  const char* names[6] = {"cov_xx", "cov_xy", "cov_xz", "cov_yy", "cov_yz", "cov_zz"};
  for (int k = 0; k < 6; ++k) columns.covariance[k] = reader.require_column(names[k]);
  return columns;
}

Gaussian3 read_gaussian(const CsvReader& reader, const CsvReader::Row& row, const GaussianColumns& columns) {
  const Vector3d mean = reader.vector3(row, columns.mean);
  const Matrix3d covariance = reader.symmetric3(row, columns.covariance);
  if (auto problem = covariance_problem(covariance)) reader.fail(row, *problem);
  try {
    return Gaussian3::from_covariance(mean, covariance);
  } catch (const std::invalid_argument& error) {
    reader.fail(row, error.what());  // at its line, whatever covariance_problem missed
  }
}

Duplicate find_first_duplicate(std::vector<RowIdentity>& rows) {
  std::sort(rows.begin(), rows.end(), [](const RowIdentity& a, const RowIdentity& b) {
    if (const int order = a.key.compare(b.key); order != 0) return order < 0;
    return a.time != b.time ? a.time < b.time : a.line < b.line;
  });
  // Of all close pairs, the one whose later line comes first in the file.
  Duplicate first;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    const RowIdentity& a = rows[k - 1];
    const RowIdentity& b = rows[k];
    if (a.key != b.key || b.time - a.time > kSameStepTolerance) continue;
    const RowIdentity& later = a.line < b.line ? b : a;
    if (first.line == 0 || later.line < first.line) first = {later.line, std::min(a.line, b.line), later.index};
  }
  return first;
}

void throw_duplicate(const std::string& path, const Duplicate& duplicate, const std::string& description) {
  throw InputError(path, duplicate.line,
                   "duplicate row for " + description + " (first at line " + std::to_string(duplicate.first_line) + ")");
}

std::string csv_field(const std::string& text) {
  const bool plain = !text.empty() && text.find_first_of(",\"\n\r") == std::string::npos &&
                     text.front() != ' ' && text.back() != ' ' && text.front() != '\t' && text.back() != '\t';
  if (plain) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  quoted += '"';
  return quoted;
}

void append_number(std::string& out, double value, int precision) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, precision);
  if (result.ec != std::errc()) throw std::invalid_argument("number cannot be written");
  out.append(buffer, result.ptr);
}

void append_time(std::string& out, double seconds) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, seconds, std::chars_format::fixed, 6);
  // The readers bound times (input_bounds.hpp); a time from elsewhere that does not fit is a bug.
  if (result.ec != std::errc()) throw std::invalid_argument("time " + std::to_string(seconds) + " s cannot be written");
  out.append(buffer, result.ptr);
}

void append_key(std::string& out, const std::string& scene, double time, const std::string* view,
                const std::string& object) {
  out += csv_field(scene);
  out += ',';
  append_time(out, time);
  out += ',';
  if (view != nullptr) {
    out += csv_field(*view);
    out += ',';
  }
  out += csv_field(object);
  out += ',';
}

void append_gaussian(std::string& out, const Gaussian3& gaussian) {
  const Vector3d& m = gaussian.mean();
  const Matrix3d& c = gaussian.covariance();
  for (int k = 0; k < 3; ++k) {
    append_number(out, m(k), 12);
    out += ',';
  }
  const double entries[6] = {c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)};
  for (int k = 0; k < 6; ++k) {
    append_number(out, entries[k], 9);
    if (k < 5) out += ',';
  }
}

}  // namespace stgf::detail
