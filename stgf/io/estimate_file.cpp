// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/estimate_file.hpp"

#include <fmt/format.h>

#include "stgf/io/csv_reader.hpp"
#include "stgf/io/output_file.hpp"
#include "stgf/io/record_columns.hpp"

namespace stgf {
namespace {

EstimateFile read_rows(CsvReader reader) {
  const detail::KeyColumns keys = detail::require_key_columns(reader, /*with_view=*/true);
  const detail::GaussianColumns gaussian = detail::require_gaussian_columns(reader);
  const int method = reader.require_column("method");
  EstimateFile file;
  file.path = reader.path();
  std::vector<detail::RowIdentity> identities;
  CsvReader::Row row;
  while (reader.next(row)) {
    Estimate estimate{reader.text(row, keys.scene), reader.time(row, keys.time), reader.text(row, keys.view),
                      reader.text(row, keys.object), detail::read_gaussian(reader, row, gaussian)};
    file.methods.push_back(reader.text(row, method));
    identities.push_back({file.methods.back() + '\n' + estimate.scene + '\n' + estimate.view + '\n' + estimate.object,
                          estimate.time, row.line, file.rows.size()});
    file.rows.push_back(std::move(estimate));
    file.lines.push_back(row.line);
  }
  detail::check_no_duplicate_rows(file.path, std::move(identities), [&](std::size_t k) {
    const Estimate& e = file.rows[k];
    return fmt::format("method '{}', scene '{}', t {}, view '{}', object '{}'", file.methods[k], e.scene, e.time,
                       e.view, e.object);
  });
  return file;
}

}  // namespace

EstimateFile read_estimates(const std::string& path) { return read_rows(CsvReader::open(path)); }

EstimateFile parse_estimates(const std::string& path, std::string_view text) {
  return read_rows(CsvReader::from_text(path, std::string(text)));
}

void write_estimates(const std::string& path, std::span<const Estimate> rows, const std::string& method) {
  OutputFile file(path);
  file.stream() << "scene,t,view,object," << detail::kGaussianHeader << ",method\n";
  const std::string method_field = detail::csv_field(method);
  std::string line;
  for (const Estimate& row : rows) {
    line.clear();
    detail::append_key(line, row.scene, row.time, &row.view, row.object);
    detail::append_gaussian(line, row.position);
    line += ',';
    line += method_field;
    line += '\n';
    file.stream() << line;
  }
  file.commit();
}

}  // namespace stgf
