// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/measurement_file.hpp"

#include <fmt/format.h>

#include "stgf/io/csv_reader.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/output_file.hpp"
#include "stgf/io/record_columns.hpp"
#include "stgf/io/scene_grouped_reader.hpp"

namespace stgf {
namespace {

// The rows of a measurements file: the header's checks, and each row parsed and checked. The whole-file
// and the scene-by-scene reader both read through it, so they accept and reject the same rows.
class MeasurementRows {
 public:
  explicit MeasurementRows(const CsvReader& reader)
      : keys_(detail::require_key_columns(reader, /*with_view=*/true)),
        gaussian_(detail::require_gaussian_columns(reader)),
        sensor_{reader.column_index("sensor_x"), reader.column_index("sensor_y"), reader.column_index("sensor_z")},
        arrival_(reader.column_index("arrival")) {
    const int sensor_columns = (sensor_[0] >= 0) + (sensor_[1] >= 0) + (sensor_[2] >= 0);
    if (sensor_columns != 0 && sensor_columns != 3) {
      throw InputError(reader.path(), 1, "sensor_x, sensor_y and sensor_z must be given together");
    }
    has_sensor_positions_ = sensor_columns == 3;
  }

  int scene_column() const { return keys_.scene; }

  // `file` with this file's path and column flags, and no rows.
  void start(const std::string& path, MeasurementFile& file) const {
    file.path = path;
    file.has_sensor_positions = has_sensor_positions_;
    file.has_arrival = arrival_ >= 0;
    file.rows.clear();
    file.lines.clear();
  }

  void append(const CsvReader& reader, const CsvReader::Row& row, MeasurementFile& file,
              std::vector<detail::RowIdentity>& identities) const {
    Measurement measurement{reader.text(row, keys_.scene), reader.time(row, keys_.time),
                            reader.text(row, keys_.view), reader.text(row, keys_.object),
                            detail::read_gaussian(reader, row, gaussian_), std::nullopt, std::nullopt};
    if (has_sensor_positions_) measurement.sensor_position = reader.vector3(row, sensor_);
    if (arrival_ >= 0) {
      measurement.arrival = reader.time(row, arrival_);
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

  std::string describe(const MeasurementFile& file, std::size_t row) const {
    const Measurement& m = file.rows[row];
    return fmt::format("scene '{}', t {}, view '{}', object '{}'", m.scene, m.time, m.view, m.object);
  }

 private:
  detail::KeyColumns keys_;
  detail::GaussianColumns gaussian_;
  int sensor_[3];
  int arrival_;
  bool has_sensor_positions_ = false;
};

}  // namespace

MeasurementFile read_measurements(const std::string& path) {
  return detail::read_whole_file<MeasurementFile, MeasurementRows>(CsvReader::open(path));
}

MeasurementFile parse_measurements(const std::string& path, std::string_view text) {
  return detail::read_whole_file<MeasurementFile, MeasurementRows>(CsvReader::from_text(path, std::string(text)));
}

struct MeasurementSceneReader::Impl {
  explicit Impl(CsvReader reader) : scenes(std::move(reader)) {}
  detail::SceneGroupedReader<MeasurementFile, MeasurementRows> scenes;
};

MeasurementSceneReader::MeasurementSceneReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MeasurementSceneReader::MeasurementSceneReader(MeasurementSceneReader&&) noexcept = default;
MeasurementSceneReader& MeasurementSceneReader::operator=(MeasurementSceneReader&&) noexcept = default;
MeasurementSceneReader::~MeasurementSceneReader() = default;

MeasurementSceneReader MeasurementSceneReader::open(const std::string& path) {
  return MeasurementSceneReader(std::make_unique<Impl>(CsvReader::open(path)));
}

MeasurementSceneReader MeasurementSceneReader::from_text(const std::string& path, std::string text) {
  return MeasurementSceneReader(std::make_unique<Impl>(CsvReader::from_text(path, std::move(text))));
}

std::size_t MeasurementSceneReader::read(MeasurementFile& block, std::size_t scenes) {
  impl_->scenes.rows().start(impl_->scenes.path(), block);
  std::size_t read = 0;
  while (read < scenes && impl_->scenes.read_scene(block)) ++read;
  return read;
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
