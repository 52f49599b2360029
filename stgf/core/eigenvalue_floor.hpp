// SPDX-License-Identifier: Apache-2.0
#pragma once
// A symmetric 3×3 matrix with its eigenvalues raised to a floor: the nearest covariance (floor 0) or
// a covariance kept away from singular (floor > 0) to a moment estimate that rounding or sampling left
// indefinite — Q's calibration (learn/), the history's velocity error (object_track.hpp).

#include <Eigen/Eigenvalues>

#include "stgf/core/gaussian.hpp"

namespace stgf {

// V max(Λ, floor) Vᵀ for (M + Mᵀ)/2 = V Λ Vᵀ.
inline Matrix3d with_eigenvalues_at_least(const Matrix3d& matrix, double floor) {
  const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(symmetrised(matrix));
  const Vector3d floored = eigen.eigenvalues().cwiseMax(floor);
  return eigen.eigenvectors() * floored.asDiagonal() * eigen.eigenvectors().transpose();
}

}  // namespace stgf
