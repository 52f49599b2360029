// SPDX-License-Identifier: Apache-2.0
#pragma once
// The measurements file (DESIGN §3):
//   scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz[,sensor_x,sensor_y,sensor_z][,arrival]
// One row per measurement. The sensor columns are optional as a group (all three or none); when
// present every row must fill them. The optional `arrival` column is when the measurement reached
// the fuser (seconds, the clock of `t`); when present every row must fill it, and arrival ≥ t.
//
// Reading rejects, with "FILE:LINE: reason": a missing column, a non-numeric field, NaN or
// infinity, an empty scene/view/object, a covariance that is not symmetric positive definite, a
// second row for the same (scene, t ± 1e-6 s, view, object), and an arrival more than
// kArrivalTolerance before t (the message arrived before it was measured).
//
// A file can be read whole (read_measurements) or scene by scene (MeasurementSceneReader, which
// `stgf run` uses so that memory holds a block of scenes, not the file: DESIGN §3.8). Both run every
// check above on every row; the scene-by-scene reader also needs the file grouped by scene.

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "stgf/core/records.hpp"

namespace stgf {

struct MeasurementFile {
  std::string path;                   // as given by the user
  std::vector<Measurement> rows;      // in file order
  std::vector<int> lines;             // line of each row
  bool has_sensor_positions = false;  // the sensor_x/y/z columns are present
  bool has_arrival = false;           // the arrival column is present
};

// How far (seconds) an arrival may lie before its measurement time and still be read (rounding).
inline constexpr double kArrivalTolerance = 1e-9;

MeasurementFile read_measurements(const std::string& path);
MeasurementFile parse_measurements(const std::string& path, std::string_view text);

// Reads a measurements file a block of scenes at a time. The rows of each scene must be contiguous
// (scenes in any order): a scene whose rows come again after another scene's is a SceneOrderError
// at that row (scene_order.hpp). Every row is checked as read_measurements checks it, duplicates
// within their scene (where any duplicate is), when the scene has been read.
class MeasurementSceneReader {
 public:
  // Opens the file and checks its header (InputError as read_measurements).
  static MeasurementSceneReader open(const std::string& path);
  // Reads `text` as if it were the file `path` (for tests and in-memory data).
  static MeasurementSceneReader from_text(const std::string& path, std::string text);
  MeasurementSceneReader(MeasurementSceneReader&&) noexcept;
  MeasurementSceneReader& operator=(MeasurementSceneReader&&) noexcept;
  ~MeasurementSceneReader();

  // Replaces what `block` holds with the next `scenes` scenes of the file (fewer at its end, none
  // once it is read): their rows in file order, each row's line, the path and the column flags, as
  // read_measurements gives them for the whole file. Returns the number of scenes read.
  std::size_t read(MeasurementFile& block, std::size_t scenes);

 private:
  struct Impl;
  explicit MeasurementSceneReader(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Writes the rows (with the sensor columns when every row has a sensor position, and the arrival
// column, with microsecond resolution like t, when every row has an arrival).
void write_measurements(const std::string& path, std::span<const Measurement> rows);

// A position as the writers write it: 12 significant digits (sub-micrometre at a kilometre).
std::string format_position(double metres);

}  // namespace stgf
