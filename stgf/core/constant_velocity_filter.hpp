// SPDX-License-Identifier: Apache-2.0
#pragma once
// A constant-velocity Kalman filter on an object's 3D position, updated with any number of views
// per step. It is the `mmt` baseline (DESIGN §2), after AB3DMOT's filter.
//
// State s = [p; v] ∈ R⁶ (m, m/s), covariance C (6×6). Over a step of Δt seconds:
//
//   predict:  s ← F s,  C ← F C Fᵀ + Q(Δt),   F = [I  Δt·I; 0  I],
//             Q(Δt) = diag(q_p Δt · I, q_v Δt · I)
//     q_p (m²/s) and q_v (m²/s³) are noise densities, so the added variance grows with the step
//     period and the filter behaves the same at 2 Hz and at 10 Hz.
//
//   update with views u ∈ V (H = [I 0]): the views are first fused into one measurement
//             R̄ = (Σ_u R_u⁻¹)⁻¹,  z̄ = R̄ Σ_u R_u⁻¹ z_u,
//     which is exactly equivalent to updating with each view in turn (same H, independent noise);
//     then  K = C Hᵀ (H C Hᵀ + R̄)⁻¹,  s ← s + K (z̄ − H s),
//           C ← (I − K H) C (I − K H)ᵀ + K R̄ Kᵀ   (Joseph form, symmetrised).
//
// The filter starts at the first fused measurement with zero velocity and
// C₀ = diag(σ²_p0 · I, σ²_v0 · I).

#include <span>

#include <Eigen/Core>

#include "stgf/core/gaussian.hpp"

namespace stgf {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// Defaults follow AB3DMOT's filter (P0 = 10 on position and 1e4 (m/frame)² on velocity, Q = 1 on
// position and 0.01 (m/frame)² on velocity, per frame of its 10 Hz data), converted to per-second
// units at 10 Hz so that they scale with the step period.
struct ConstantVelocityModel {
  double initial_position_variance = 10.0;  // σ²_p0, m²
  double initial_velocity_variance = 1e6;   // σ²_v0, (m/s)² — 1e4 (m/frame)² at 0.1 s/frame
  double position_noise_density = 10.0;     // q_p, m²/s — 1 m² per 0.1 s frame
  double velocity_noise_density = 10.0;     // q_v, m²/s³ — 0.01 (m/frame)² = 1 (m/s)² per 0.1 s frame
};

class ConstantVelocityFilter {
 public:
  ConstantVelocityFilter(const ConstantVelocityModel& model, const Gaussian3& first_measurement);

  // Moves the state Δt seconds ahead. Throws std::invalid_argument unless Δt ≥ 0 and finite.
  void predict(double dt);

  // Updates with one fused measurement N(z̄, R̄) (H = [I 0]).
  void update(const Gaussian3& measurement);

  // Updates with the measurements of all views that saw the object at this step (none: no change).
  void update(std::span<const Gaussian3> measurements);

  const Vector6d& state() const { return state_; }
  const Matrix6d& covariance() const { return covariance_; }
  Gaussian3 position() const;

 private:
  ConstantVelocityModel model_;
  Vector6d state_;
  Matrix6d covariance_;
};

}  // namespace stgf
