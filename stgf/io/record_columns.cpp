#include "stgf/io/record_columns.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "stgf/core/records.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/measurement_file.hpp"

namespace stgf::detail {

const char* const kGaussianHeader = "x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz";

KeyColumns require_key_columns(const CsvTable& table, bool with_view) {
  KeyColumns columns;
  columns.scene = table.require_column("scene");
  columns.time = table.require_column("t");
  if (with_view) columns.view = table.require_column("view");
  columns.object = table.require_column("object");
  return columns;
}

void require_position_columns(const CsvTable& table, int (&columns)[3]) {
  columns[0] = table.require_column("x");
  columns[1] = table.require_column("y");
  columns[2] = table.require_column("z");
}

GaussianColumns require_gaussian_columns(const CsvTable& table) {
  GaussianColumns columns{};
  require_position_columns(table, columns.mean);
  const char* names[6] = {"cov_xx", "cov_xy", "cov_xz", "cov_yy", "cov_yz", "cov_zz"};
  for (int k = 0; k < 6; ++k) columns.covariance[k] = table.require_column(names[k]);
  return columns;
}

Gaussian3 read_gaussian(const CsvTable& table, const CsvTable::Row& row, const GaussianColumns& columns) {
  const Vector3d mean = table.vector3(row, columns.mean);
  const Matrix3d covariance = table.symmetric3(row, columns.covariance);
  if (auto problem = covariance_problem(covariance)) table.fail(row, *problem);
  return Gaussian3::from_covariance(mean, covariance);
}

void check_no_duplicate_rows(const std::string& path, std::size_t count,
                             const std::function<std::string(std::size_t)>& key_of,
                             const std::function<double(std::size_t)>& time_of,
                             const std::function<int(std::size_t)>& line_of,
                             const std::function<std::string(std::size_t)>& describe) {
  std::vector<std::string> keys(count);
  for (std::size_t k = 0; k < count; ++k) keys[k] = key_of(k);
  std::vector<std::size_t> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (keys[a] != keys[b]) return keys[a] < keys[b];
    return time_of(a) != time_of(b) ? time_of(a) < time_of(b) : line_of(a) < line_of(b);
  });
  // The first duplicate in file order: the smallest later line among all close pairs.
  int worst_line = 0;
  std::string message;
  for (std::size_t k = 1; k < order.size(); ++k) {
    const std::size_t a = order[k - 1], b = order[k];
    if (keys[a] != keys[b] || time_of(b) - time_of(a) > kSameStepTolerance) continue;
    const std::size_t later = line_of(a) < line_of(b) ? b : a;
    const int first = std::min(line_of(a), line_of(b)), second = line_of(later);
    if (worst_line == 0 || second < worst_line) {
      worst_line = second;
      message = "duplicate row for " + describe(later) + " (first at line " + std::to_string(first) + ")";
    }
  }
  if (worst_line != 0) throw InputError(path, worst_line, message);
}

std::string csv_field(const std::string& text) {
  const bool plain = text.find_first_of(",\"\n\r") == std::string::npos && !text.empty() &&
                     text.front() != ' ' && text.back() != ' ' && text.front() != '\t' &&
                     text.back() != '\t';
  if (plain) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + '"';
}

std::string format_gaussian(const Gaussian3& gaussian) {
  const Vector3d& m = gaussian.mean();
  const Matrix3d& c = gaussian.covariance();
  return fmt::format("{},{},{},{},{},{},{},{},{}", format_position(m.x()), format_position(m.y()),
                     format_position(m.z()), format_covariance_entry(c(0, 0)),
                     format_covariance_entry(c(0, 1)), format_covariance_entry(c(0, 2)),
                     format_covariance_entry(c(1, 1)), format_covariance_entry(c(1, 2)),
                     format_covariance_entry(c(2, 2)));
}

}  // namespace stgf::detail
