// SPDX-License-Identifier: Apache-2.0
#pragma once
// The loops that read a file whole or scene by scene (internal to the io layer), shared by the
// measurement, truth and estimate readers. Scene by scene: each scene's rows are parsed by the same
// code as the whole file's, their duplicates checked when the scene ends (a duplicate is always
// within one scene), and a scene that comes back after another one is a SceneOrderError at its first
// returning row.
//
// `Rows` is the file kind's row reader:
//   explicit Rows(const CsvReader&)   checks the header (InputError at line 1)
//   int scene_column() const
//   void start(const std::string& path, File&) const   empties the file and gives it the path (and
//                                     whatever else the header says of it)
//   void append(const CsvReader&, const CsvReader::Row&, File&, std::vector<RowIdentity>&) const
//                                     parses the row, appends it to the file and its identity
//   std::string describe(const File&, std::size_t row) const   names a row in a duplicate message

#include <string>
#include <utility>
#include <vector>

#include "stgf/io/csv_reader.hpp"
#include "stgf/io/record_columns.hpp"
#include "stgf/io/scene_order.hpp"

namespace stgf::detail {

// The whole file: every row parsed by `Rows`, then the duplicates checked.
template <class File, class Rows>
File read_whole_file(CsvReader reader) {
  const Rows rows(reader);
  File file;
  rows.start(reader.path(), file);
  std::vector<RowIdentity> identities;
  CsvReader::Row row;
  while (reader.next(row)) rows.append(reader, row, file, identities);
  check_no_duplicate_rows(file.path, std::move(identities), [&](std::size_t k) { return rows.describe(file, k); });
  return file;
}

template <class File, class Rows>
class SceneGroupedReader {
 public:
  explicit SceneGroupedReader(CsvReader reader) : reader_(std::move(reader)), rows_(reader_) {
    has_row_ = reader_.next(row_);
    if (has_row_) order_.opens_scene(reader_.path(), row_.line, scene_of_row(), 0);
  }

  const std::string& path() const { return reader_.path(); }
  const Rows& rows() const { return rows_; }

  // Appends the rows of the next scene to `file`; false at the end of the file.
  bool read_scene(File& file) {
    if (!has_row_) return false;
    const std::string scene = scene_of_row();
    std::vector<RowIdentity> identities;
    int last_line = 0;
    do {
      rows_.append(reader_, row_, file, identities);
      last_line = row_.line;
      has_row_ = reader_.next(row_);
    } while (has_row_ && scene_of_row() == scene);
    check_no_duplicate_rows(reader_.path(), std::move(identities),
                            [&](std::size_t row) { return rows_.describe(file, row); });
    if (has_row_) order_.opens_scene(reader_.path(), row_.line, scene_of_row(), last_line);
    return true;
  }

 private:
  const std::string& scene_of_row() const { return reader_.text(row_, rows_.scene_column()); }

  CsvReader reader_;
  Rows rows_;
  SceneOrder order_;
  CsvReader::Row row_;    // the first row of the next scene, read ahead
  bool has_row_ = false;  // false at the end of the file
};

}  // namespace stgf::detail
