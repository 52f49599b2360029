// SPDX-License-Identifier: Apache-2.0
#pragma once
// Cholesky factorisation of a symmetric 3×3 matrix, A = L Lᵀ, written out in full. It is the one
// matrix solve in the fusion hot path, so it is unrolled rather than left to a general routine:
//
//   l₀₀ = √a₀₀            l₁₀ = a₁₀ / l₀₀               l₂₀ = a₂₀ / l₀₀
//   l₁₁ = √(a₁₁ − l₁₀²)    l₂₁ = (a₂₁ − l₂₀ l₁₀) / l₁₁    l₂₂ = √(a₂₂ − l₂₀² − l₂₁²)
//
// M = L⁻¹ is lower triangular:
//   m₀₀ = 1/l₀₀, m₁₁ = 1/l₁₁, m₂₂ = 1/l₂₂,
//   m₁₀ = −l₁₀ m₀₀ m₁₁,  m₂₁ = −l₂₁ m₁₁ m₂₂,  m₂₀ = −(l₂₀ m₀₀ + l₂₁ m₁₀) m₂₂
// and A⁻¹ = Mᵀ M, which is symmetric by construction. Only the lower triangle of A is read.

#include <cmath>

#include <Eigen/Core>

namespace stgf {

class Cholesky3 {
 public:
  explicit Cholesky3(const Eigen::Matrix3d& a) {
    const double p0 = a(0, 0);
    ok_ = p0 > 0.0;
    if (!ok_) return;
    l00_ = std::sqrt(p0);
    l10_ = a(1, 0) / l00_;
    l20_ = a(2, 0) / l00_;
    const double p1 = a(1, 1) - l10_ * l10_;
    ok_ = p1 > 0.0;
    if (!ok_) return;
    l11_ = std::sqrt(p1);
    l21_ = (a(2, 1) - l20_ * l10_) / l11_;
    const double p2 = a(2, 2) - l20_ * l20_ - l21_ * l21_;
    ok_ = p2 > 0.0 && std::isfinite(p2);
    if (!ok_) return;
    l22_ = std::sqrt(p2);
  }

  // False unless A is positive definite (every pivot positive and finite).
  bool ok() const { return ok_; }

  // M = L⁻¹ (lower triangular). Requires ok().
  Eigen::Matrix3d inverse_factor() const {
    const InverseFactor m = inverse_factor_entries();
    Eigen::Matrix3d result;
    result << m.m00, 0, 0, m.m10, m.m11, 0, m.m20, m.m21, m.m22;
    return result;
  }

  // A⁻¹ = Mᵀ M. Requires ok().
  Eigen::Matrix3d inverse() const {
    const auto [m00, m11, m22, m10, m21, m20] = inverse_factor_entries();
    Eigen::Matrix3d inverse;
    inverse(0, 0) = m00 * m00 + m10 * m10 + m20 * m20;
    inverse(1, 1) = m11 * m11 + m21 * m21;
    inverse(2, 2) = m22 * m22;
    inverse(0, 1) = inverse(1, 0) = m10 * m11 + m20 * m21;
    inverse(0, 2) = inverse(2, 0) = m20 * m22;
    inverse(1, 2) = inverse(2, 1) = m21 * m22;
    return inverse;
  }

  // det A = (l₀₀ l₁₁ l₂₂)². Requires ok().
  double determinant() const {
    const double product = l00_ * l11_ * l22_;
    return product * product;
  }

  Eigen::Matrix3d matrix_l() const {
    Eigen::Matrix3d l;
    l << l00_, 0, 0, l10_, l11_, 0, l20_, l21_, l22_;
    return l;
  }

 private:
  struct InverseFactor {
    double m00, m11, m22, m10, m21, m20;
  };
  InverseFactor inverse_factor_entries() const {
    const double m00 = 1.0 / l00_, m11 = 1.0 / l11_, m22 = 1.0 / l22_;
    const double m10 = -l10_ * m00 * m11;
    const double m21 = -l21_ * m11 * m22;
    const double m20 = -(l20_ * m00 + l21_ * m10) * m22;
    return {m00, m11, m22, m10, m21, m20};
  }

  bool ok_ = false;
  double l00_ = 0, l10_ = 0, l20_ = 0, l11_ = 0, l21_ = 0, l22_ = 0;
};

}  // namespace stgf
