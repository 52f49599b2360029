// SPDX-License-Identifier: Apache-2.0
#pragma once
// Column handling shared by the measurement, truth and estimate files (internal to the io layer).

#include <string>
#include <vector>

#include "stgf/core/gaussian.hpp"
#include "stgf/io/csv_reader.hpp"

namespace stgf::detail {

struct KeyColumns {
  int scene = -1, time = -1, view = -1, object = -1;  // view is -1 for the truth file
};
KeyColumns require_key_columns(const CsvReader& reader, bool with_view);

struct GaussianColumns {
  int mean[3];
  int covariance[6];  // xx, xy, xz, yy, yz, zz
};
GaussianColumns require_gaussian_columns(const CsvReader& reader);
void require_position_columns(const CsvReader& reader, int (&columns)[3]);

// The row's position and covariance; a covariance that is not SPD fails with the file and line.
Gaussian3 read_gaussian(const CsvReader& reader, const CsvReader::Row& row, const GaussianColumns& columns);

// The identity of a row apart from its time, for finding duplicates.
struct RowIdentity {
  std::string key;
  double time;
  int line;
  std::size_t index;  // into the caller's rows
};

// Fails at the later line when two rows share a key and their times differ by at most 1e-6 s.
// `describe(index)` names the row for the message.
template <class Describe>
void check_no_duplicate_rows(const std::string& path, std::vector<RowIdentity> rows, const Describe& describe);

// `text` as one CSV field: quoted when it holds a comma, a quote, or surrounding blanks.
std::string csv_field(const std::string& text);

// The header of the Gaussian columns, "x,y,z,cov_xx,...,cov_zz".
extern const char* const kGaussianHeader;
// Appends the values of those columns: positions with 12 significant digits (sub-micrometre at a
// kilometre), covariance entries with 9.
void append_gaussian(std::string& out, const Gaussian3& gaussian);
// Appends `value` with `precision` significant digits (shortest form, like %g) or, for times,
// with microsecond resolution.
void append_number(std::string& out, double value, int precision);
void append_time(std::string& out, double seconds);
// Appends "scene,t,[view,]object," — the key columns every stgf file starts with.
void append_key(std::string& out, const std::string& scene, double time, const std::string* view,
                const std::string& object);

// --- implementation ---

struct Duplicate {
  int line = 0;           // the later line; 0 when there is no duplicate
  int first_line = 0;     // the earlier line
  std::size_t index = 0;  // the later row's index
};
Duplicate find_first_duplicate(std::vector<RowIdentity>& rows);
[[noreturn]] void throw_duplicate(const std::string& path, const Duplicate& duplicate, const std::string& description);

template <class Describe>
void check_no_duplicate_rows(const std::string& path, std::vector<RowIdentity> rows, const Describe& describe) {
  const Duplicate duplicate = find_first_duplicate(rows);
  if (duplicate.line != 0) throw_duplicate(path, duplicate, describe(duplicate.index));
}

}  // namespace stgf::detail
