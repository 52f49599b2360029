// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/slope_response.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace stgf {

Vector3d slope_tilt(const Matrix3d& velocity_variance, double typical_speed) {
  // Below a hundredth of the typical speed the forecast's change would be near its rounding (Φ runs in
  // single precision); beyond the typical speed Φ would read a motion unlike any it learnt from.
  const double low = 0.01 * typical_speed, high = typical_speed;
  Vector3d tilt;
  for (int a = 0; a < 3; ++a) {
    tilt[a] = std::clamp(std::sqrt(std::max(velocity_variance(a, a), 0.0)), low, high);
  }
  return tilt;
}

MotionGraph tilted_graph(const MotionGraph& graph, std::span<const Vector3d> tilts) {
  if (tilts.size() != graph.objects.size()) throw std::invalid_argument("tilted_graph: one tilt per object");
  MotionGraph tilted = graph;
  for (std::size_t i = 0; i < tilted.objects.size(); ++i) {
    ObjectHistory& history = tilted.objects[i];
    const double last = history.times.back();
    for (std::size_t k = 0; k < history.positions.size(); ++k) {
      history.positions[k] += tilts[i] * (history.times[k] - last);
    }
  }
  return tilted;
}

MotionForecast with_slope_response(MotionForecast forecast, const MotionForecast& tilted,
                                   const Vector3d& tilt) {
  forecast.velocity_response = (tilted.velocity - forecast.velocity).cwiseQuotient(tilt);
  forecast.acceleration_response = (tilted.acceleration - forecast.acceleration).cwiseQuotient(tilt);
  return forecast;
}

}  // namespace stgf
