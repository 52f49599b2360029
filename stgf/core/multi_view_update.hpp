// SPDX-License-Identifier: Apache-2.0
#pragma once
// The multi-view update of the spatiotemporal graph filter (paper Eqs. 10–13, DESIGN §1.3).
//
// A prior N(x, P) on an object's position and the measurements N(z_u, R_u) of the views u ∈ V that
// saw it at this step are fused in information form:
//
//   S  = P⁻¹ + Σ_u R_u⁻¹                 (information of the posterior)
//   P̂  = S⁻¹                              (Cholesky solve, symmetrised)
//   E  = P̂ P⁻¹,   M_u = P̂ R_u⁻¹          (state and measurement gains; E + Σ_u M_u = I)
//   x̂  = E x + Σ_u M_u z_u  =  P̂ (P⁻¹ x + Σ_u R_u⁻¹ z_u)
//
// With one view this is the Kalman update with H = I (paper Theorems 1–2): M = P (P + R)⁻¹ = K and
// P̂ = (I − K) P. With no view the posterior is the prior. Without a prior (zero information) the
// result is the information-weighted mean of the measurements, the `wls` estimate.
//
// Every R_u has been validated when its Gaussian3 was built (symmetric positive definite), and each
// information matrix is computed once, so the update itself is a sum and one 3×3 Cholesky solve.

#include <span>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

// Accumulates Gaussians in information form: Λ = Σ Λ_k, η = Σ Λ_k μ_k.
class InformationSum {
 public:
  void add(const Gaussian3& gaussian) {
    information_ += gaussian.information();
    information_vector_ += gaussian.information() * gaussian.mean();
    ++count_;
  }
  int count() const { return count_; }

  // N(Λ⁻¹ η, Λ⁻¹). Throws std::logic_error when nothing was added.
  Gaussian3 solve() const;

 private:
  Matrix3d information_ = Matrix3d::Zero();
  Vector3d information_vector_ = Vector3d::Zero();
  int count_ = 0;
};

// The fused estimate N(x̂, P̂) of a prior and any number of view measurements (possibly none).
Gaussian3 multi_view_update(const Gaussian3& prior, std::span<const Gaussian3> measurements);

// The information-weighted mean of one or more measurements: N((Σ R_u⁻¹)⁻¹ Σ R_u⁻¹ z_u, (Σ R_u⁻¹)⁻¹).
// Throws std::invalid_argument when `measurements` is empty.
Gaussian3 information_weighted_mean(std::span<const Gaussian3> measurements);

// The gains of the paper, for inspection and tests; multi_view_update does not need them.
struct MultiViewGains {
  Matrix3d state_gain;                         // E = P̂ P⁻¹
  std::vector<Matrix3d> measurement_gains;     // M_u = P̂ R_u⁻¹, one per measurement, in order
};
MultiViewGains multi_view_gains(const Gaussian3& prior, std::span<const Gaussian3> measurements);

}  // namespace stgf
