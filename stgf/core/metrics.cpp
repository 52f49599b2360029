// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/metrics.hpp"

namespace stgf {

void ErrorAccumulator::add(const Gaussian3& estimate, const Vector3d& truth,
                           const std::optional<Vector3d>& sensor_position) {
  const double displacement = (estimate.mean() - truth).norm();
  const double nees = estimate.mahalanobis_squared(truth);
  ++rows_;
  displacement_sum_ += displacement;
  nees_sum_ += nees;
  // The marginals: (x, y) under P̂'s upper-left block [a b; b d], whose inverse is [d −b; −b a] / (ad − b²);
  // z under P̂_zz.
  const Matrix3d& p = estimate.covariance();
  const Vector3d error = estimate.mean() - truth;
  const double x = error.x(), y = error.y();
  nees_horizontal_sum_ += (p(1, 1) * x * x - 2.0 * p(0, 1) * x * y + p(0, 0) * y * y) / (p(0, 0) * p(1, 1) - p(0, 1) * p(0, 1));
  nees_vertical_sum_ += error.z() * error.z() / p(2, 2);
  if (nees >= kChiSquare3Lower95 && nees <= kChiSquare3Upper95) ++nees_inside_;
  if (sensor_position) {
    const double range = (truth - *sensor_position).norm();
    if (range > 0.0) {
      relative_displacement_sum_ += displacement / range;
      ++rows_with_range_;
    }
  }
}

ErrorSummary ErrorAccumulator::summary() const {
  ErrorSummary summary;
  summary.rows = rows_;
  if (rows_ == 0) return summary;
  const auto n = static_cast<double>(rows_);
  summary.displacement_error = displacement_sum_ / n;
  summary.nees_mean = nees_sum_ / n;
  summary.nees_share_in_95 = static_cast<double>(nees_inside_) / n;
  summary.nees_horizontal_mean = nees_horizontal_sum_ / n;
  summary.nees_vertical_mean = nees_vertical_sum_ / n;
  if (rows_with_range_ == rows_) summary.relative_displacement_error = relative_displacement_sum_ / n;
  return summary;
}

}  // namespace stgf
