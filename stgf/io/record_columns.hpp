#pragma once
// Column handling shared by the measurement, truth and estimate files (internal to the io layer).

#include <functional>
#include <string>
#include <vector>

#include "stgf/core/gaussian.hpp"
#include "stgf/io/csv_table.hpp"

namespace stgf::detail {

struct KeyColumns {
  int scene = -1, time = -1, view = -1, object = -1;  // view is -1 for the truth file
};
KeyColumns require_key_columns(const CsvTable& table, bool with_view);

struct GaussianColumns {
  int mean[3];
  int covariance[6];  // xx, xy, xz, yy, yz, zz
};
GaussianColumns require_gaussian_columns(const CsvTable& table);
void require_position_columns(const CsvTable& table, int (&columns)[3]);

// The row's position and covariance; a covariance that is not SPD fails with the file and line.
Gaussian3 read_gaussian(const CsvTable& table, const CsvTable::Row& row, const GaussianColumns& columns);

// Fails at the later line when two rows share a key and their times differ by at most 1e-6 s.
// `key_of(k)` is the identity of row k apart from the time; `describe(k)` names it for the message.
void check_no_duplicate_rows(const std::string& path, std::size_t count,
                             const std::function<std::string(std::size_t)>& key_of,
                             const std::function<double(std::size_t)>& time_of,
                             const std::function<int(std::size_t)>& line_of,
                             const std::function<std::string(std::size_t)>& describe);

// `text` as one CSV field: quoted when it holds a comma, a quote, or surrounding blanks.
std::string csv_field(const std::string& text);

// The header line of a file with a Gaussian: "...,x,y,z,cov_xx,...,cov_zz".
extern const char* const kGaussianHeader;
// "x,y,z,cov_xx,...,cov_zz" values of a Gaussian, formatted.
std::string format_gaussian(const Gaussian3& gaussian);

}  // namespace stgf::detail
