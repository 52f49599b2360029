// SPDX-License-Identifier: Apache-2.0
#pragma once
// A measurement that the other views of its object, at the same time, place far off keeps little weight.
//
// Without the gate (off by default: measurement_gate.hpp) a gross error — a false detection, a swapped
// identity — was fused as its R said. With the views' offsets estimated jointly (joint_registration.hpp)
// it moved not only its object's position but its view's offset, and so every later measurement of that
// view, the far ones most where the offset grows with range (design §1.7, the range scale): on the mpl
// test split with one view's measurements 2 % gross outliers `ours` had DE 0.3138 m where `wls` has
// 0.1128 m. The other views of the object at the same time tell such an error without any motion model
// (neither the prediction nor its Q plays a part, so data unlike the model's training data does not make
// good measurements look bad, as it can for the gate).
//
// Each measurement k, corrected for its view's offset, is N(c_k, s_k N_k + O_k): N_k its noise (μR,
// the view's noise scale μ), O_k the offset's share H_u Σ_uu H_uᵀ, s_k ≥ 1 the scale sought (1 to begin
// with). Against the information-weighted mean N(m₋ₖ, M₋ₖ) of the others,
//     ν_k = c_k − m₋ₖ,    d²_k(s) = ν_kᵀ (s N_k + O_k + M₋ₖ)⁻¹ ν_k  ~ χ²(3) when all of them are right.
// The offsets' shares are taken independent between views. That bounds ν's covariance from above once
// the offsets are learnt (the part of them common to the views then cancels in the difference), so the
// test errs towards keeping a measurement's weight.
// While some d²_k exceeds γ (the χ²(3) quantile kProbability = 0.999: 16.27, as the gate's), the one with
// the largest d² gets the smallest s_k that brings its d²_k(s_k) to γ, and the others are judged again
// against means with it so scaled: a gross error also pulls the others' leave-one-out means by its share
// of them, but its own d² is the largest (with equal R, four times the others' for three views). Each
// measurement is scaled at most once, and at most n − 2 of n, so that two or more keep their stated
// noise: where fewer than three views measure the object, two that disagree do not say which is wrong, and
// they are left as they are (the gate's business, with the object's prediction).
// Soft, not a cut: a measurement just past γ keeps most of its weight, one metres off (s ≈ d²/γ) hardly
// any; its position's covariance says how much the others alone know. Each scaled measurement is
// counted per view and `stgf run` logs the counts.

#include <cstddef>
#include <span>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

class CrossViewWeights {
 public:
  static constexpr double kProbability = 0.999;

  struct Measurement {
    Vector3d corrected;  // c_k
    Matrix3d noise;      // N_k, positive definite
    Matrix3d offset;     // O_k, positive semi-definite
  };
  // s_k for each measurement (1 for those kept as stated; all 1 for fewer than three).
  static std::vector<double> noise_scales(std::span<const Measurement> measurements);
  static double threshold();  // γ
};

}  // namespace stgf
