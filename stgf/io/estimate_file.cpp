// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/estimate_file.hpp"

#include <fmt/format.h>

#include "stgf/io/csv_reader.hpp"
#include "stgf/io/record_columns.hpp"
#include "stgf/io/scene_grouped_reader.hpp"

namespace stgf {
namespace {

// The rows of an estimates file, read whole or scene by scene through the same checks.
class EstimateRows {
 public:
  explicit EstimateRows(const CsvReader& reader)
      : keys_(detail::require_key_columns(reader, /*with_view=*/true)),
        gaussian_(detail::require_gaussian_columns(reader)),
        method_(reader.require_column("method")) {}

  int scene_column() const { return keys_.scene; }

  void start(const std::string& path, EstimateFile& file) const {
    file.path = path;
    file.rows.clear();
    file.methods.clear();
    file.lines.clear();
  }

  void append(const CsvReader& reader, const CsvReader::Row& row, EstimateFile& file,
              std::vector<detail::RowIdentity>& identities) const {
    Estimate estimate{reader.text(row, keys_.scene), reader.time(row, keys_.time), reader.text(row, keys_.view),
                      reader.text(row, keys_.object), detail::read_gaussian(reader, row, gaussian_)};
    file.methods.push_back(reader.text(row, method_));
    identities.push_back({file.methods.back() + '\n' + estimate.scene + '\n' + estimate.view + '\n' + estimate.object,
                          estimate.time, row.line, file.rows.size()});
    file.rows.push_back(std::move(estimate));
    file.lines.push_back(row.line);
  }

  std::string describe(const EstimateFile& file, std::size_t row) const {
    const Estimate& e = file.rows[row];
    return fmt::format("method '{}', scene '{}', t {}, view '{}', object '{}'", file.methods[row], e.scene, e.time,
                       e.view, e.object);
  }

 private:
  detail::KeyColumns keys_;
  detail::GaussianColumns gaussian_;
  int method_;
};

}  // namespace

EstimateFile read_estimates(const std::string& path) {
  return detail::read_whole_file<EstimateFile, EstimateRows>(CsvReader::open(path));
}

EstimateFile parse_estimates(const std::string& path, std::string_view text) {
  return detail::read_whole_file<EstimateFile, EstimateRows>(CsvReader::from_text(path, std::string(text)));
}

struct EstimateSceneReader::Impl {
  explicit Impl(CsvReader reader) : scenes(std::move(reader)) {}
  detail::SceneGroupedReader<EstimateFile, EstimateRows> scenes;
};

EstimateSceneReader::EstimateSceneReader(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
EstimateSceneReader::EstimateSceneReader(EstimateSceneReader&&) noexcept = default;
EstimateSceneReader& EstimateSceneReader::operator=(EstimateSceneReader&&) noexcept = default;
EstimateSceneReader::~EstimateSceneReader() = default;

EstimateSceneReader EstimateSceneReader::open(const std::string& path) {
  return EstimateSceneReader(std::make_unique<Impl>(CsvReader::open(path)));
}

EstimateSceneReader EstimateSceneReader::from_text(const std::string& path, std::string text) {
  return EstimateSceneReader(std::make_unique<Impl>(CsvReader::from_text(path, std::move(text))));
}

bool EstimateSceneReader::read(EstimateFile& scene) {
  impl_->scenes.rows().start(impl_->scenes.path(), scene);
  return impl_->scenes.read_scene(scene);
}

EstimateWriter::EstimateWriter(const std::string& path, const std::string& method)
    : file_(path), method_field_(detail::csv_field(method)) {
  file_.stream() << "scene,t,view,object," << detail::kGaussianHeader << ",method\n";
}

void EstimateWriter::write(const std::string& scene, double time, const std::string& view, const std::string& object,
                           const Gaussian3& position) {
  line_.clear();
  detail::append_key(line_, scene, time, &view, object);
  detail::append_gaussian(line_, position);
  line_ += ',';
  line_ += method_field_;
  line_ += '\n';
  file_.stream() << line_;
}

void EstimateWriter::commit() { file_.commit(); }

void write_estimates(const std::string& path, std::span<const Estimate> rows, const std::string& method) {
  EstimateWriter writer(path, method);
  for (const Estimate& row : rows) writer.write(row.scene, row.time, row.view, row.object, row.position);
  writer.commit();
}

}  // namespace stgf
