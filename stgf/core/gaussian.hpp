// SPDX-License-Identifier: Apache-2.0
#pragma once
// A 3D Gaussian N(mean, covariance) whose covariance is known to be symmetric positive definite.
//
// The class keeps the information matrix Λ = covariance⁻¹ next to the covariance, computed once by a
// Cholesky solve when the Gaussian is made, so that fusing many Gaussians never inverts the same
// matrix twice. The only ways to build one check the covariance, so code that receives a Gaussian3
// can rely on it.

#include <optional>
#include <string>

#include <Eigen/Core>

namespace stgf {

using Eigen::Matrix3d;
using Eigen::Vector3d;

// Why `covariance` cannot be a covariance, or nullopt when it can. A covariance must be finite,
// symmetric (to a relative 1e-9 of its largest entry) and positive definite with a condition number
// below 1e12; its smallest eigenvalue is named in the reason when it is not.
std::optional<std::string> covariance_problem(const Matrix3d& covariance);

class Gaussian3 {
 public:
  // Checks the covariance (see covariance_problem) and throws std::invalid_argument with the reason.
  // The stored covariance is the symmetric part (C + Cᵀ)/2.
  static Gaussian3 from_covariance(const Vector3d& mean, const Matrix3d& covariance);

  // Builds the Gaussian from its canonical (information) form Λ = covariance⁻¹, η = Λ mean:
  // one Cholesky factorisation Λ = L Lᵀ gives covariance = Λ⁻¹ and mean = Λ⁻¹ η.
  // Throws std::invalid_argument when Λ is not positive definite.
  static Gaussian3 from_information(const Vector3d& information_vector, const Matrix3d& information);

  const Vector3d& mean() const { return mean_; }
  const Matrix3d& covariance() const { return covariance_; }
  const Matrix3d& information() const { return information_; }

  // The same Gaussian with its mean moved by `shift` (nothing to check again).
  Gaussian3 moved_by(const Vector3d& shift) const { return Gaussian3(mean_ + shift, covariance_, information_); }

  // Squared Mahalanobis distance (p − mean)ᵀ covariance⁻¹ (p − mean).
  double mahalanobis_squared(const Vector3d& point) const;

 private:
  Gaussian3(const Vector3d& mean, const Matrix3d& covariance, const Matrix3d& information)
      : mean_(mean), covariance_(covariance), information_(information) {}

  Vector3d mean_;
  Matrix3d covariance_;
  Matrix3d information_;
};

// (M + Mᵀ)/2: removes the asymmetry that rounding leaves in a product of symmetric matrices.
inline Matrix3d symmetrised(const Matrix3d& matrix) { return 0.5 * (matrix + matrix.transpose()); }
// The average of T M Tᵀ over every turn T about the vertical axis: the horizontal block becomes
// ½ (M_xx + M_yy) I, the horizontal–vertical terms 0, M_zz stays. A covariance that does not depend
// on the world frame's heading.
inline Matrix3d averaged_over_headings(const Matrix3d& matrix) {
  const double horizontal = 0.5 * (matrix(0, 0) + matrix(1, 1));
  Matrix3d averaged = Matrix3d::Zero();
  averaged(0, 0) = averaged(1, 1) = horizontal;
  averaged(2, 2) = matrix(2, 2);
  return averaged;
}

}  // namespace stgf
