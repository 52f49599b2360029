// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/line_of_sight.hpp"

#include <cmath>

// last: applies to this file's functions only
#include "stgf/datasets/fp_contract_off.hpp"

namespace stgf {
namespace {

double dot3(const Vector3d& a, const Vector3d& b) { return a.x() * b.x() + a.y() * b.y() + a.z() * b.z(); }

}  // namespace

Matrix3d LineOfSightNoise::covariance() const {
  Matrix3d covariance;
  for (int row = 0; row < 3; ++row) {
    for (int column = 0; column < 3; ++column) {
      double sum = 0.0;
      for (int axis = 0; axis < 3; ++axis) {
        const double variance = standard_deviations(axis) * standard_deviations(axis);
        sum += variance * (basis(row, axis) * basis(column, axis));  // symmetric in (row, column) bit for bit
      }
      covariance(row, column) = sum;
    }
  }
  return covariance;
}

Matrix3d LineOfSightNoise::square_root() const {
  Matrix3d root;
  for (int row = 0; row < 3; ++row) {
    for (int axis = 0; axis < 3; ++axis) root(row, axis) = basis(row, axis) * standard_deviations(axis);
  }
  return root;
}

LineOfSightNoise line_of_sight(const Vector3d& sensor, const Vector3d& target) {
  const Vector3d offset = target - sensor;
  const double range = std::sqrt(dot3(offset, offset));
  LineOfSightNoise noise;
  noise.range = range;

  // u_r; straight down when the target is at the sensor itself (then any basis will do).
  const Vector3d along = range > 0.0 ? Vector3d(offset / range) : Vector3d(0.0, 0.0, -1.0);
  const double horizontal = std::sqrt(along.x() * along.x() + along.y() * along.y());
  // u_c horizontal and across; along x when the line of sight is vertical.
  const Vector3d across = horizontal > 1e-12 ? Vector3d(-along.y() / horizontal, along.x() / horizontal, 0.0)
                                             : Vector3d(1.0, 0.0, 0.0);
  const Vector3d vertical(along.y() * across.z() - along.z() * across.y(),
                          along.z() * across.x() - along.x() * across.z(),
                          along.x() * across.y() - along.y() * across.x());  // u_r × u_c
  noise.basis.col(0) = along;
  noise.basis.col(1) = across;
  noise.basis.col(2) = vertical;
  return noise;
}

double range_detection_probability(double range_m, double max_range_m, double probability_near,
                                   double probability_far) {
  if (!(range_m <= max_range_m)) return 0.0;
  const double fraction = range_m / max_range_m;
  return probability_near - (probability_near - probability_far) * (fraction * fraction);
}

}  // namespace stgf
