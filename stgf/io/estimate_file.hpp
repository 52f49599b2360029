// SPDX-License-Identifier: Apache-2.0
#pragma once
// The estimates file (DESIGN §3):
//   scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,method
// One row per (scene, t, view, object) estimate; the method column names what produced it.
// It can be read whole (read_estimates) or scene by scene (EstimateSceneReader, for `stgf eval`:
// DESIGN §3.8) with the same checks, and written whole (write_estimates) or row by row as the rows
// come (EstimateWriter, for `stgf run`); either way it appears whole or not at all.

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "stgf/core/records.hpp"
#include "stgf/io/output_file.hpp"

namespace stgf {

struct EstimateFile {
  std::string path;
  std::vector<Estimate> rows;
  std::vector<std::string> methods;  // method of each row
  std::vector<int> lines;
};

EstimateFile read_estimates(const std::string& path);
EstimateFile parse_estimates(const std::string& path, std::string_view text);
void write_estimates(const std::string& path, std::span<const Estimate> rows, const std::string& method);

// Reads an estimates file one scene at a time, like MeasurementSceneReader (measurement_file.hpp):
// the rows of each scene must be contiguous (SceneOrderError otherwise), every row is checked as
// read_estimates checks it, duplicates within their scene.
class EstimateSceneReader {
 public:
  static EstimateSceneReader open(const std::string& path);
  static EstimateSceneReader from_text(const std::string& path, std::string text);
  EstimateSceneReader(EstimateSceneReader&&) noexcept;
  EstimateSceneReader& operator=(EstimateSceneReader&&) noexcept;
  ~EstimateSceneReader();

  // Replaces what `scene` holds with the next scene's rows, methods and lines; false at the end of
  // the file.
  bool read(EstimateFile& scene);

 private:
  struct Impl;
  explicit EstimateSceneReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Writes an estimates file a row at a time, through an OutputFile: the rows go to a temporary file as
// they come, and only commit() puts the file in place. Destroyed without commit() (an error on the
// way), it leaves no file and whatever `path` held before untouched. The bytes are write_estimates'.
class EstimateWriter {
 public:
  EstimateWriter(const std::string& path, const std::string& method);  // writes the header
  void write(const std::string& scene, double time, const std::string& view, const std::string& object,
             const Gaussian3& position);
  void commit();

 private:
  OutputFile file_;
  std::string method_field_;
  std::string line_;
};

}  // namespace stgf
