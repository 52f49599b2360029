// SPDX-License-Identifier: Apache-2.0
#pragma once
// Sensor noise along and across the line of sight, and misses that grow with range: the model that
// the synthetic, cad and ethucy benchmarks share (each chooses its own standard deviations; see
// synthetic.hpp and cad_benchmark.hpp).
//
// ── The line-of-sight basis ─────────────────────────────────────────────────────────────────────
// For a sensor at s and a target at p, the range r = ‖p − s‖ and U = [u_r u_c u_v] with
//   u_r = (p − s)/r                  along the range; straight down (0, 0, −1) when r = 0
//   u_c = (−u_r,y, u_r,x, 0)/‖·‖     across, horizontal; (1, 0, 0) when the line of sight is vertical
//   u_v = u_r × u_c                  across, in the vertical plane of the line of sight
// U is orthonormal with det U = +1.
//
// ── Noise along those axes ──────────────────────────────────────────────────────────────────────
// With standard deviations σ = (σ_r, σ_c, σ_v) along u_r, u_c, u_v:
//   R = U diag(σ²) Uᵀ,   R_ij = Σ_k σ_k² (U_ik U_jk)   (k = 0, 1, 2 in this order, so R_ij and R_ji
//                                                       are the same bits: R is exactly symmetric)
//   S = U diag(σ),       S_ik = U_ik σ_k,  S Sᵀ = R
// so z = p + S ξ with ξ ~ N(0, I₃) has z − p ~ N(0, R) exactly: R is the true error covariance and
// the NEES (z − p)ᵀ R⁻¹ (z − p) is χ²₃ (mean 3, variance 6).
//
// ── Misses ──────────────────────────────────────────────────────────────────────────────────────
// A target at range r is detected with probability
//   P_d(r) = P_near − (P_near − P_far) (r / max_range)²   for r ≤ max_range,   0 beyond (and for NaN).
//
// The arithmetic is written out in a fixed order (see fp_contract_off.hpp), so that the benchmarks
// built on it are byte-identical on every platform.

#include "stgf/core/gaussian.hpp"

namespace stgf {

// U, σ and r of one sensor and target (σ is the caller's: line_of_sight leaves it zero).
struct LineOfSightNoise {
  Matrix3d basis;                                   // U = [u_r u_c u_v], orthonormal columns
  Vector3d standard_deviations = Vector3d::Zero();  // (σ_r, σ_c, σ_v)
  double range = 0.0;                               // r (m)

  Matrix3d covariance() const;   // R = U diag(σ²) Uᵀ, exactly symmetric
  Matrix3d square_root() const;  // S = U diag(σ), so that square_root() square_root()ᵀ = R
};

// r and U from `sensor` to `target`; standard_deviations zero.
LineOfSightNoise line_of_sight(const Vector3d& sensor, const Vector3d& target);

// P_d(range_m) (see above).
double range_detection_probability(double range_m, double max_range_m, double probability_near,
                                   double probability_far);

}  // namespace stgf
