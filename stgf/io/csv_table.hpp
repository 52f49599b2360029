#pragma once
// A small CSV reader for stgf's files (DESIGN §3): a header row names the columns, which may come
// in any order; unknown columns are ignored. Fields are separated by commas and may be quoted with
// double quotes ("" inside a quoted field is one quote). Surrounding spaces are trimmed; CRLF line
// ends and a UTF-8 byte-order mark are accepted; blank lines are skipped. Every failure is an
// InputError naming the file and the line.

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace stgf {

class CsvTable {
 public:
  struct Row {
    int line;  // 1-based line number in the file (the header is line 1)
    std::vector<std::string> fields;
  };

  // Reads the whole file. Throws InputError when it cannot be opened, is empty, has a header with
  // an empty or repeated name, or a row whose field count differs from the header's.
  static CsvTable read(const std::string& path);
  // Parses text as if it were the file `path` (for tests and in-memory data).
  static CsvTable parse(const std::string& path, std::string_view text);

  const std::string& path() const { return path_; }
  const std::vector<Row>& rows() const { return rows_; }
  bool has_column(std::string_view name) const { return column_index(name) >= 0; }

  // Index of a column that must exist; InputError at line 1 otherwise.
  int require_column(std::string_view name) const;
  // -1 when absent.
  int column_index(std::string_view name) const;

  // A non-empty string field.
  const std::string& text(const Row& row, int column) const;
  // A finite decimal number (InputError for non-numeric text, NaN or infinity).
  double number(const Row& row, int column) const;

  // The 3-vector in columns `names` and the symmetric 3×3 matrix from the six columns
  // xx, xy, xz, yy, yz, zz.
  Eigen::Vector3d vector3(const Row& row, const int (&columns)[3]) const;
  Eigen::Matrix3d symmetric3(const Row& row, const int (&columns)[6]) const;

  [[noreturn]] void fail(const Row& row, const std::string& what) const;

 private:
  std::string path_;
  std::vector<std::string> header_;
  std::vector<Row> rows_;
};

}  // namespace stgf
