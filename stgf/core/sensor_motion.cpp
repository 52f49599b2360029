// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/sensor_motion.hpp"

#include <map>
#include <string_view>

namespace stgf {

SensorMotion sensor_motion(std::span<const Measurement> measurements, const Scene& scene) {
  std::map<std::string_view, Vector3d> first_position;  // of each view that gives one
  for (const Step& step : scene.steps) {
    for (std::size_t row : step.rows) {
      const Measurement& measurement = measurements[row];
      if (!measurement.sensor_position) continue;
      const auto [first, inserted] = first_position.try_emplace(measurement.view, *measurement.sensor_position);
      if (!inserted && (*measurement.sensor_position - first->second).norm() > kMovingSensorDistance) {
        return SensorMotion::kMoving;
      }
    }
  }
  return SensorMotion::kFixed;
}

}  // namespace stgf
