// SPDX-License-Identifier: Apache-2.0
#pragma once
// The truth file (DESIGN §3): scene,t,object,x,y,z — the true position of each object at each time.
// Reading rejects bad rows like the measurements reader, and a second row for the same
// (scene, t ± 1e-6 s, object). It can be read whole (read_truth) or scene by scene
// (TruthSceneReader, for `stgf eval`: DESIGN §3.8), with the same checks.

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "stgf/core/records.hpp"

namespace stgf {

struct TruthFile {
  std::string path;
  std::vector<TruthPoint> rows;
  std::vector<int> lines;
};

TruthFile read_truth(const std::string& path);
TruthFile parse_truth(const std::string& path, std::string_view text);

// Reads a truth file one scene at a time, like MeasurementSceneReader (measurement_file.hpp): the
// rows of each scene must be contiguous (SceneOrderError otherwise), every row is checked as
// read_truth checks it, duplicates within their scene.
class TruthSceneReader {
 public:
  static TruthSceneReader open(const std::string& path);
  static TruthSceneReader from_text(const std::string& path, std::string text);
  TruthSceneReader(TruthSceneReader&&) noexcept;
  TruthSceneReader& operator=(TruthSceneReader&&) noexcept;
  ~TruthSceneReader();

  // Replaces what `scene` holds with the next scene's rows and lines; false at the end of the file.
  bool read(TruthFile& scene);

 private:
  struct Impl;
  explicit TruthSceneReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};
void write_truth(const std::string& path, std::span<const TruthPoint> rows);

// Finds the truth of (scene, time ± 1e-6 s, object).
class TruthIndex {
 public:
  explicit TruthIndex(const TruthFile& truth);
  std::optional<Vector3d> find(std::string_view scene, double time, std::string_view object) const;
  bool has_scene(std::string_view scene) const;

 private:
  struct Sample {
    double time;
    Vector3d position;
  };
  // scene + '\n' + object → samples sorted by time.
  std::unordered_map<std::string, std::vector<Sample>> samples_;
  std::unordered_map<std::string, int> scenes_;
};

struct MeasurementFile;

// Every measurement has a truth row, and every truth scene has measurements; InputError naming the
// first offending line otherwise ("measurement without truth when truth is given").
void check_truth_matches(const MeasurementFile& measurements, const TruthFile& truth);

}  // namespace stgf
