// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/gaussian.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>

#include "stgf/core/cholesky3.hpp"

namespace stgf {
namespace {

constexpr double kSymmetryTolerance = 1e-9;
constexpr double kMaxConditionNumber = 1e12;

std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

// Λ = C⁻¹ by a Cholesky factorisation C = L Lᵀ; nullopt when C is not positive definite.
std::optional<Matrix3d> inverse_by_cholesky(const Matrix3d& matrix) {
  const Cholesky3 cholesky(matrix);
  if (!cholesky.ok()) return std::nullopt;
  return cholesky.inverse();
}

// The checks of covariance_problem that need no eigenvalues: finite, symmetric, and a sufficient test
// of a condition number below 1e12 — for C positive definite, λ_max ≤ tr C and
// λ_min ≥ det C / (tr C / 2)² (the other two eigenvalues' product is at most ((tr C) / 2)²), so
// tr³ ≤ 4 · 1e12 · det bounds it. Passed: the factor of the symmetric part, whose inverse is Λ.
std::optional<Cholesky3> vouched_factor(const Matrix3d& covariance) {
  if (!covariance.allFinite()) return std::nullopt;
  const double scale = covariance.cwiseAbs().maxCoeff();
  if (scale == 0.0 || (covariance - covariance.transpose()).cwiseAbs().maxCoeff() > kSymmetryTolerance * scale) {
    return std::nullopt;
  }
  const Matrix3d symmetric = symmetrised(covariance);
  const Cholesky3 cholesky(symmetric);
  const double trace = symmetric.trace();
  if (cholesky.ok() && trace * trace * trace <= 4.0 * kMaxConditionNumber * cholesky.determinant()) return cholesky;
  return std::nullopt;
}

}  // namespace

std::optional<std::string> covariance_problem(const Matrix3d& covariance) {
  if (!covariance.allFinite()) return "covariance has a NaN or infinite entry";
  const double scale = covariance.cwiseAbs().maxCoeff();
  if (scale == 0.0) return "covariance is zero";
  if ((covariance - covariance.transpose()).cwiseAbs().maxCoeff() > kSymmetryTolerance * scale) {
    return "covariance is not symmetric";
  }
  // The sufficient test first; only what it cannot vouch for is examined below.
  if (vouched_factor(covariance)) return std::nullopt;
  Eigen::SelfAdjointEigenSolver<Matrix3d> eigen;
  eigen.computeDirect(symmetrised(covariance), Eigen::EigenvaluesOnly);
  const double smallest = eigen.eigenvalues()(0);
  const double largest = eigen.eigenvalues()(2);
  if (!(smallest > 0.0)) {
    return "covariance is not positive definite (smallest eigenvalue " + format_number(smallest) + ")";
  }
  // The closed-form eigenvalues lose the small ones when the scales differ a lot (found by fuzzing:
  // a 2×2 block with a negative determinant beside a variance of 5e9); the Cholesky factorisation
  // that from_covariance inverts with decides.
  if (!inverse_by_cholesky(symmetrised(covariance))) {
    return "covariance is not positive definite (Cholesky factorisation fails)";
  }
  if (largest > kMaxConditionNumber * smallest) {
    return "covariance is nearly singular (eigenvalues " + format_number(smallest) + " to " +
           format_number(largest) + ")";
  }
  return std::nullopt;
}

Gaussian3 Gaussian3::from_covariance(const Vector3d& mean, const Matrix3d& covariance) {
  if (!mean.allFinite()) throw std::invalid_argument("mean has a NaN or infinite entry");
  // What passes the sufficient test keeps its factor: Λ from it, one factorisation instead of two.
  if (const std::optional<Cholesky3> factor = vouched_factor(covariance)) {
    return Gaussian3(mean, symmetrised(covariance), factor->inverse());
  }
  if (auto problem = covariance_problem(covariance)) throw std::invalid_argument(*problem);
  const Matrix3d symmetric = symmetrised(covariance);
  const auto information = inverse_by_cholesky(symmetric);
  if (!information) throw std::invalid_argument("covariance is not positive definite");
  return Gaussian3(mean, symmetric, *information);
}

Gaussian3 Gaussian3::from_information(const Vector3d& information_vector,
                                      const Matrix3d& information) {
  const Matrix3d symmetric = symmetrised(information);
  const auto covariance = inverse_by_cholesky(symmetric);
  if (!covariance || !symmetric.allFinite()) {
    throw std::invalid_argument("information matrix is not positive definite");
  }
  const Vector3d mean = *covariance * information_vector;
  if (!mean.allFinite()) throw std::invalid_argument("mean has a NaN or infinite entry");
  return Gaussian3(mean, *covariance, symmetric);
}

double Gaussian3::mahalanobis_squared(const Vector3d& point) const {
  const Vector3d difference = point - mean_;
  return difference.dot(information_ * difference);
}

}  // namespace stgf
