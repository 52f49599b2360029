// SPDX-License-Identifier: Apache-2.0
#pragma once
// A symmetric 3×3 matrix with its eigenvalues raised to a floor: the nearest covariance (floor 0) or
// a covariance kept away from singular (floor > 0) to a moment estimate that rounding or sampling left
// indefinite — Q's calibration (learn/), the history's velocity error (object_track.hpp).
// And a change of a covariance that may take variance away, held so that the sum stays one.

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "stgf/core/gaussian.hpp"

namespace stgf {

// V max(Λ, floor) Vᵀ for (M + Mᵀ)/2 = V Λ Vᵀ.
inline Matrix3d with_eigenvalues_at_least(const Matrix3d& matrix, double floor) {
  const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(symmetrised(matrix));
  const Vector3d floored = eigen.eigenvalues().cwiseMax(floor);
  return eigen.eigenvectors() * floored.asDiagonal() * eigen.eigenvectors().transpose();
}

// `matrix` where it is a covariance (positive semidefinite), bit for bit; else the nearest one, its
// eigenvalues raised to 0: for a sum of terms that should make a covariance but, where the model holds
// only approximately, may not (the history's velocity error, object_track.hpp; what a step adds to a
// frame's path, frame_alignment.hpp).
inline Matrix3d nearest_covariance(const Matrix3d& matrix) {
  if (Eigen::LDLT<Matrix3d>(matrix).isPositive()) return matrix;
  return with_eigenvalues_at_least(matrix, 0.0);
}

// `change`, or, where it would take more than half of `covariance`'s least variance away, the change
// that leaves covariance + change with its eigenvalues raised to that half: a prediction that is more
// certain than the state it came from (object_track.hpp: a forecast that brings a height back toward
// its history's) never makes the state's covariance singular. A covariance `change` is returned as it is.
inline Matrix3d grown_within(const Matrix3d& covariance, const Matrix3d& change) {
  if (Eigen::LDLT<Matrix3d>(change).isPositive()) return change;
  using Eigenvalues = Eigen::SelfAdjointEigenSolver<Matrix3d>;
  const double least = Eigenvalues(covariance, Eigen::EigenvaluesOnly).eigenvalues()[0];
  const Matrix3d sum = symmetrised(covariance + change);
  if (Eigenvalues(sum, Eigen::EigenvaluesOnly).eigenvalues()[0] >= 0.5 * least) return change;
  return symmetrised(with_eigenvalues_at_least(sum, 0.5 * least) - covariance);
}

}  // namespace stgf
