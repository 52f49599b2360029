// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/truth_file.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "stgf/io/csv_reader.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/output_file.hpp"
#include "stgf/io/record_columns.hpp"
#include "stgf/io/scene_grouped_reader.hpp"

namespace stgf {
namespace {

// The rows of a truth file, read whole or scene by scene through the same checks.
class TruthRows {
 public:
  explicit TruthRows(const CsvReader& reader) : keys_(detail::require_key_columns(reader, /*with_view=*/false)) {
    detail::require_position_columns(reader, position_);
  }

  int scene_column() const { return keys_.scene; }

  void start(const std::string& path, TruthFile& file) const {
    file.path = path;
    file.rows.clear();
    file.lines.clear();
  }

  void append(const CsvReader& reader, const CsvReader::Row& row, TruthFile& file,
              std::vector<detail::RowIdentity>& identities) const {
    TruthPoint point{reader.text(row, keys_.scene), reader.time(row, keys_.time), reader.text(row, keys_.object),
                     reader.vector3(row, position_)};
    identities.push_back({point.scene + '\n' + point.object, point.time, row.line, file.rows.size()});
    file.rows.push_back(std::move(point));
    file.lines.push_back(row.line);
  }

  std::string describe(const TruthFile& file, std::size_t row) const {
    const TruthPoint& p = file.rows[row];
    return fmt::format("scene '{}', t {}, object '{}'", p.scene, p.time, p.object);
  }

 private:
  detail::KeyColumns keys_;
  int position_[3];
};

std::string scene_object_key(std::string_view scene, std::string_view object) {
  std::string key(scene);
  key += '\n';
  key += object;
  return key;
}

}  // namespace

TruthFile read_truth(const std::string& path) {
  return detail::read_whole_file<TruthFile, TruthRows>(CsvReader::open(path));
}

TruthFile parse_truth(const std::string& path, std::string_view text) {
  return detail::read_whole_file<TruthFile, TruthRows>(CsvReader::from_text(path, std::string(text)));
}

struct TruthSceneReader::Impl {
  explicit Impl(CsvReader reader) : scenes(std::move(reader)) {}
  detail::SceneGroupedReader<TruthFile, TruthRows> scenes;
};

TruthSceneReader::TruthSceneReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
TruthSceneReader::TruthSceneReader(TruthSceneReader&&) noexcept = default;
TruthSceneReader& TruthSceneReader::operator=(TruthSceneReader&&) noexcept = default;
TruthSceneReader::~TruthSceneReader() = default;

TruthSceneReader TruthSceneReader::open(const std::string& path) {
  return TruthSceneReader(std::make_unique<Impl>(CsvReader::open(path)));
}

TruthSceneReader TruthSceneReader::from_text(const std::string& path, std::string text) {
  return TruthSceneReader(std::make_unique<Impl>(CsvReader::from_text(path, std::move(text))));
}

bool TruthSceneReader::read(TruthFile& scene) {
  impl_->scenes.rows().start(impl_->scenes.path(), scene);
  return impl_->scenes.read_scene(scene);
}

void write_truth(const std::string& path, std::span<const TruthPoint> rows) {
  OutputFile file(path);
  file.stream() << "scene,t,object,x,y,z\n";
  std::string line;
  for (const TruthPoint& row : rows) {
    line.clear();
    detail::append_key(line, row.scene, row.time, nullptr, row.object);
    for (int k = 0; k < 3; ++k) {
      detail::append_number(line, row.position(k), 12);
      if (k < 2) line += ',';
    }
    line += '\n';
    file.stream() << line;
  }
  file.commit();
}

TruthIndex::TruthIndex(const TruthFile& truth) {
  for (const TruthPoint& point : truth.rows) {
    samples_[scene_object_key(point.scene, point.object)].push_back(Sample{point.time, point.position});
    ++scenes_[point.scene];
  }
  for (auto& [key, samples] : samples_) {
    std::sort(samples.begin(), samples.end(),
              [](const Sample& a, const Sample& b) { return a.time < b.time; });
  }
}

std::optional<Vector3d> TruthIndex::find(std::string_view scene, double time,
                                         std::string_view object) const {
  const auto it = samples_.find(scene_object_key(scene, object));
  if (it == samples_.end()) return std::nullopt;
  const std::vector<Sample>& samples = it->second;
  const auto candidate = std::lower_bound(
      samples.begin(), samples.end(), time - kSameStepTolerance,
      [](const Sample& sample, double value) { return sample.time < value; });
  if (candidate == samples.end() || candidate->time > time + kSameStepTolerance) return std::nullopt;
  return candidate->position;
}

bool TruthIndex::has_scene(std::string_view scene) const {
  return scenes_.find(std::string(scene)) != scenes_.end();
}

void check_truth_matches(const MeasurementFile& measurements, const TruthFile& truth) {
  const TruthIndex index(truth);
  std::unordered_map<std::string, int> measured_scenes;
  for (std::size_t k = 0; k < measurements.rows.size(); ++k) {
    const Measurement& row = measurements.rows[k];
    if (!index.find(row.scene, row.time, row.object)) {
      throw InputError(measurements.path, measurements.lines[k],
                       fmt::format("no truth for scene '{}', t {}, object '{}' in {}", row.scene,
                                   row.time, row.object, truth.path));
    }
    ++measured_scenes[row.scene];
  }
  for (std::size_t k = 0; k < truth.rows.size(); ++k) {
    if (measured_scenes.find(truth.rows[k].scene) == measured_scenes.end()) {
      throw InputError(truth.path, truth.lines[k],
                       fmt::format("scene '{}' has no measurements in {}", truth.rows[k].scene,
                                   measurements.path));
    }
  }
}

}  // namespace stgf
