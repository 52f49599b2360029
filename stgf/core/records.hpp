// SPDX-License-Identifier: Apache-2.0
#pragma once
// The records stgf reads and writes (DESIGN §3). A measurement describes itself — scene, time,
// view, object, position with its covariance, and where the sensor was — so any number of views
// works without new code. Units are metres and seconds.

#include <optional>
#include <string>

#include "stgf/core/gaussian.hpp"

namespace stgf {

// Times closer than this (seconds) belong to the same step.
inline constexpr double kSameStepTolerance = 1e-6;

struct Measurement {
  std::string scene;
  double time = 0.0;
  std::string view;
  std::string object;
  Gaussian3 position;                       // z and its covariance R
  std::optional<Vector3d> sensor_position;  // where the view's sensor was at `time`, when known
  // When the measurement reached the fuser (seconds, same clock as `time`, >= time), when known: a
  // fuser processes rows in arrival order, so a row can come after rows measured later than it.
  std::optional<double> arrival;
};

// An estimate of one object's position held by one view at one time.
struct Estimate {
  std::string scene;
  double time = 0.0;
  std::string view;
  std::string object;
  Gaussian3 position;  // x̂ and P̂
};

// The true position of an object at a time.
struct TruthPoint {
  std::string scene;
  double time = 0.0;
  std::string object;
  Vector3d position;
};

}  // namespace stgf
