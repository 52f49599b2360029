#include "stgf/io/measurement_file.hpp"

#include <fmt/format.h>

#include "stgf/io/csv_table.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/output_file.hpp"
#include "stgf/io/record_columns.hpp"

namespace stgf {
namespace {

MeasurementFile measurements_from_table(const CsvTable& table) {
  const detail::KeyColumns keys = detail::require_key_columns(table, /*with_view=*/true);
  const detail::GaussianColumns gaussian = detail::require_gaussian_columns(table);
  const int sensor_present = static_cast<int>(table.has_column("sensor_x")) +
                             static_cast<int>(table.has_column("sensor_y")) +
                             static_cast<int>(table.has_column("sensor_z"));
  if (sensor_present != 0 && sensor_present != 3) {
    throw InputError(table.path(), 1, "sensor_x, sensor_y and sensor_z must be given together");
  }
  int sensor[3] = {-1, -1, -1};
  if (sensor_present == 3) {
    sensor[0] = table.column_index("sensor_x");
    sensor[1] = table.column_index("sensor_y");
    sensor[2] = table.column_index("sensor_z");
  }

  MeasurementFile file;
  file.path = table.path();
  file.has_sensor_positions = sensor_present == 3;
  file.rows.reserve(table.rows().size());
  file.lines.reserve(table.rows().size());
  for (const CsvTable::Row& row : table.rows()) {
    Measurement measurement{table.text(row, keys.scene), table.number(row, keys.time),
                            table.text(row, keys.view), table.text(row, keys.object),
                            detail::read_gaussian(table, row, gaussian), std::nullopt};
    if (file.has_sensor_positions) measurement.sensor_position = table.vector3(row, sensor);
    file.rows.push_back(std::move(measurement));
    file.lines.push_back(row.line);
  }
  const auto& rows = file.rows;
  detail::check_no_duplicate_rows(
      file.path, rows.size(),
      [&](std::size_t k) { return rows[k].scene + '\n' + rows[k].view + '\n' + rows[k].object; },
      [&](std::size_t k) { return rows[k].time; }, [&](std::size_t k) { return file.lines[k]; },
      [&](std::size_t k) {
        return fmt::format("scene '{}', t {}, view '{}', object '{}'", rows[k].scene, rows[k].time,
                           rows[k].view, rows[k].object);
      });
  return file;
}

}  // namespace

MeasurementFile read_measurements(const std::string& path) {
  return measurements_from_table(CsvTable::read(path));
}

MeasurementFile parse_measurements(const std::string& path, std::string_view text) {
  return measurements_from_table(CsvTable::parse(path, text));
}

std::string format_time(double seconds) { return fmt::format("{:.6f}", seconds); }
std::string format_position(double metres) { return fmt::format("{:.12g}", metres); }
std::string format_covariance_entry(double value) { return fmt::format("{:.9g}", value); }

void write_measurements(const std::string& path, std::span<const Measurement> rows) {
  bool with_sensor = !rows.empty();
  for (const Measurement& row : rows) with_sensor = with_sensor && row.sensor_position.has_value();
  OutputFile file(path);
  std::ofstream& out = file.stream();
  out << "scene,t,view,object," << detail::kGaussianHeader
      << (with_sensor ? ",sensor_x,sensor_y,sensor_z\n" : "\n");
  for (const Measurement& row : rows) {
    out << detail::csv_field(row.scene) << ',' << format_time(row.time) << ','
        << detail::csv_field(row.view) << ',' << detail::csv_field(row.object) << ','
        << detail::format_gaussian(row.position);
    if (with_sensor) {
      const Vector3d& s = *row.sensor_position;
      out << ',' << format_position(s.x()) << ',' << format_position(s.y()) << ','
          << format_position(s.z());
    }
    out << '\n';
  }
  file.commit();
}

}  // namespace stgf
