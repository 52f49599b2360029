// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/average_of_measurements.hpp"

#include "stgf/methods/object_groups.hpp"

namespace stgf {

std::vector<Gaussian3> AverageOfMeasurements::step(double /*time*/,
                                                   std::span<const Measurement* const> measurements) {
  return estimate_per_object(measurements, [](const ObjectGroup& group) {
    Vector3d sum = Vector3d::Zero();
    Matrix3d covariance_sum = Matrix3d::Zero();
    for (const Gaussian3& measurement : group.measurements) {
      sum += measurement.mean();
      covariance_sum += measurement.covariance();
    }
    const auto n = static_cast<double>(group.measurements.size());
    return Gaussian3::from_covariance(sum / n, covariance_sum / (n * n));
  });
}

}  // namespace stgf
