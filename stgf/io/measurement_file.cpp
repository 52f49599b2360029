// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/measurement_file.hpp"

#include <fmt/format.h>

#include "stgf/io/csv_reader.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/output_file.hpp"
#include "stgf/io/record_columns.hpp"

namespace stgf {
namespace {

MeasurementFile read_rows(CsvReader reader) {
  const detail::KeyColumns keys = detail::require_key_columns(reader, /*with_view=*/true);
  const detail::GaussianColumns gaussian = detail::require_gaussian_columns(reader);
  const int sensor[3] = {reader.column_index("sensor_x"), reader.column_index("sensor_y"),
                         reader.column_index("sensor_z")};
  const int sensor_columns = (sensor[0] >= 0) + (sensor[1] >= 0) + (sensor[2] >= 0);
  if (sensor_columns != 0 && sensor_columns != 3) {
    throw InputError(reader.path(), 1, "sensor_x, sensor_y and sensor_z must be given together");
  }

  const int arrival = reader.column_index("arrival");

  MeasurementFile file;
  file.path = reader.path();
  file.has_sensor_positions = sensor_columns == 3;
  file.has_arrival = arrival >= 0;
  std::vector<detail::RowIdentity> identities;
  CsvReader::Row row;
  while (reader.next(row)) {
    Measurement measurement{reader.text(row, keys.scene), reader.time(row, keys.time),
                            reader.text(row, keys.view), reader.text(row, keys.object),
                            detail::read_gaussian(reader, row, gaussian), std::nullopt, std::nullopt};
    if (file.has_sensor_positions) measurement.sensor_position = reader.vector3(row, sensor);
    if (file.has_arrival) {
      measurement.arrival = reader.time(row, arrival);
      if (*measurement.arrival < measurement.time - kArrivalTolerance) {
        reader.fail(row, fmt::format("arrival {} is before t {}: the message arrived before it was measured",
                                     *measurement.arrival, measurement.time));
      }
    }
    identities.push_back({measurement.scene + '\n' + measurement.view + '\n' + measurement.object,
                          measurement.time, row.line, file.rows.size()});
    file.rows.push_back(std::move(measurement));
    file.lines.push_back(row.line);
  }
  detail::check_no_duplicate_rows(file.path, std::move(identities), [&](std::size_t k) {
    const Measurement& m = file.rows[k];
    return fmt::format("scene '{}', t {}, view '{}', object '{}'", m.scene, m.time, m.view, m.object);
  });
  return file;
}

}  // namespace

MeasurementFile read_measurements(const std::string& path) { return read_rows(CsvReader::open(path)); }

MeasurementFile parse_measurements(const std::string& path, std::string_view text) {
  return read_rows(CsvReader::from_text(path, std::string(text)));
}

std::string format_position(double metres) {
  std::string text;
  detail::append_number(text, metres, 12);
  return text;
}

void write_measurements(const std::string& path, std::span<const Measurement> rows) {
  bool with_sensor = !rows.empty();
  bool with_arrival = !rows.empty();
  for (const Measurement& row : rows) {
    with_sensor = with_sensor && row.sensor_position.has_value();
    with_arrival = with_arrival && row.arrival.has_value();
  }
  OutputFile file(path);
  std::string line = std::string("scene,t,view,object,") + detail::kGaussianHeader +
                     (with_sensor ? ",sensor_x,sensor_y,sensor_z" : "") + (with_arrival ? ",arrival\n" : "\n");
  file.stream() << line;
  for (const Measurement& row : rows) {
    line.clear();
    detail::append_key(line, row.scene, row.time, &row.view, row.object);
    detail::append_gaussian(line, row.position);
    if (with_sensor) {
      for (int k = 0; k < 3; ++k) {
        line += ',';
        detail::append_number(line, (*row.sensor_position)(k), 12);
      }
    }
    if (with_arrival) {
      line += ',';
      detail::append_time(line, *row.arrival);
    }
    line += '\n';
    file.stream() << line;
  }
  file.commit();
}

}  // namespace stgf
