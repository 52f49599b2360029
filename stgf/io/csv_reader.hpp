// SPDX-License-Identifier: Apache-2.0
#pragma once
// A small streaming CSV reader for stgf's files (DESIGN §3): a header row names the columns, which
// may come in any order; unknown columns are ignored. Fields are separated by commas and may be
// quoted with double quotes ("" inside a quoted field is one quote). Surrounding blanks are
// trimmed; CRLF line ends and a UTF-8 byte-order mark are accepted; blank lines are skipped. Rows
// are read one at a time, so a file never has to fit in memory twice. Every failure is an
// InputError naming the file and the line.

#include <istream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace stgf {

class CsvReader {
 public:
  struct Row {
    int line = 0;  // 1-based line number in the file (the header is line 1)
    std::vector<std::string> fields;
  };

  // Opens the file and reads its header. Throws InputError when it cannot be opened, is empty, or
  // has a header with an empty or repeated name.
  static CsvReader open(const std::string& path);
  // Reads `text` as if it were the file `path` (for tests and in-memory data).
  static CsvReader from_text(const std::string& path, std::string text);

  // The next data row; false at the end of the file. Throws InputError for a row whose field count
  // differs from the header's or an unterminated quote.
  bool next(Row& row);

  const std::string& path() const { return path_; }
  bool has_column(std::string_view name) const { return column_index(name) >= 0; }
  // -1 when absent.
  int column_index(std::string_view name) const;
  // Index of a column that must exist; InputError at line 1 otherwise.
  int require_column(std::string_view name) const;

  // A non-empty string field.
  const std::string& text(const Row& row, int column) const;
  // A finite decimal number (InputError for non-numeric text, NaN or infinity).
  double number(const Row& row, int column) const;
  // The 3-vector in `columns` and the symmetric 3×3 matrix from the six columns xx, xy, xz, yy, yz, zz.
  // A number with |value| ≤ max_abs; `what` names the bound in the message (input_bounds.hpp).
  double bounded_number(const Row& row, int column, double max_abs, const char* what) const;
  // A time (s) within kMaxAbsTime.
  double time(const Row& row, int column) const;
  // Three coordinates (m) within kMaxAbsCoordinate.
  Eigen::Vector3d vector3(const Row& row, const int (&columns)[3]) const;
  // A symmetric matrix from its six upper entries, its diagonal positive and within
  // [kMinVariance, kMaxVariance]; positive definiteness is checked by the caller (covariance_problem).
  Eigen::Matrix3d symmetric3(const Row& row, const int (&columns)[6]) const;

  [[noreturn]] void fail(const Row& row, const std::string& what) const;

 private:
  // "column 'NAME': 'FIELD'", both quoted in part when long.
  std::string column_and_field(const Row& row, int column) const;
  CsvReader(std::string path, std::unique_ptr<std::istream> input);
  void read_header();
  // The next non-blank line, without its line end; false at the end.
  bool next_line(std::string& line);

  std::string path_;
  std::unique_ptr<std::istream> input_;
  int line_number_ = 0;
  std::string line_;
  std::vector<std::string> header_;
};

}  // namespace stgf
