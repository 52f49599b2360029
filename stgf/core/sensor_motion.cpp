// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/sensor_motion.hpp"

namespace stgf {

void SensorMotionWatch::see(const Measurement& measurement) {
  if (motion_ == SensorMotion::kMoving || !measurement.sensor_position) return;
  const auto first = first_position_.find(measurement.view);
  if (first == first_position_.end()) {
    first_position_.emplace(measurement.view, *measurement.sensor_position);
  } else if ((*measurement.sensor_position - first->second).norm() > kMovingSensorDistance) {
    motion_ = SensorMotion::kMoving;
  }
}

SensorMotion sensor_motion(std::span<const Measurement> measurements, const Scene& scene) {
  SensorMotionWatch watch;
  for (const Step& step : scene.steps) {
    for (std::size_t row : step.rows) {
      watch.see(measurements[row]);
      if (watch.motion() == SensorMotion::kMoving) return SensorMotion::kMoving;
    }
  }
  return SensorMotion::kFixed;
}

}  // namespace stgf
