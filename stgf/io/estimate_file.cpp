#include "stgf/io/estimate_file.hpp"

#include <fmt/format.h>

#include "stgf/io/csv_table.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/output_file.hpp"
#include "stgf/io/record_columns.hpp"

namespace stgf {
namespace {

EstimateFile estimates_from_table(const CsvTable& table) {
  const detail::KeyColumns keys = detail::require_key_columns(table, /*with_view=*/true);
  const detail::GaussianColumns gaussian = detail::require_gaussian_columns(table);
  const int method = table.require_column("method");
  EstimateFile file;
  file.path = table.path();
  file.rows.reserve(table.rows().size());
  for (const CsvTable::Row& row : table.rows()) {
    file.rows.push_back(Estimate{table.text(row, keys.scene), table.number(row, keys.time),
                                 table.text(row, keys.view), table.text(row, keys.object),
                                 detail::read_gaussian(table, row, gaussian)});
    file.methods.push_back(table.text(row, method));
    file.lines.push_back(row.line);
  }
  const auto& rows = file.rows;
  detail::check_no_duplicate_rows(
      file.path, rows.size(),
      [&](std::size_t k) {
        return file.methods[k] + '\n' + rows[k].scene + '\n' + rows[k].view + '\n' + rows[k].object;
      },
      [&](std::size_t k) { return rows[k].time; }, [&](std::size_t k) { return file.lines[k]; },
      [&](std::size_t k) {
        return fmt::format("method '{}', scene '{}', t {}, view '{}', object '{}'", file.methods[k],
                           rows[k].scene, rows[k].time, rows[k].view, rows[k].object);
      });
  return file;
}

}  // namespace

EstimateFile read_estimates(const std::string& path) { return estimates_from_table(CsvTable::read(path)); }

EstimateFile parse_estimates(const std::string& path, std::string_view text) {
  return estimates_from_table(CsvTable::parse(path, text));
}

void write_estimates(const std::string& path, std::span<const Estimate> rows, const std::string& method) {
  OutputFile file(path);
  std::ofstream& out = file.stream();
  out << "scene,t,view,object," << detail::kGaussianHeader << ",method\n";
  const std::string method_field = detail::csv_field(method);
  for (const Estimate& row : rows) {
    out << detail::csv_field(row.scene) << ',' << format_time(row.time) << ','
        << detail::csv_field(row.view) << ',' << detail::csv_field(row.object) << ','
        << detail::format_gaussian(row.position) << ',' << method_field << '\n';
  }
  file.commit();
}

}  // namespace stgf
