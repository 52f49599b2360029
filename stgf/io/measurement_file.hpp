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

// Writes the rows (with the sensor columns when every row has a sensor position, and the arrival
// column, with microsecond resolution like t, when every row has an arrival).
void write_measurements(const std::string& path, std::span<const Measurement> rows);

// A position as the writers write it: 12 significant digits (sub-micrometre at a kilometre).
std::string format_position(double metres);

}  // namespace stgf
