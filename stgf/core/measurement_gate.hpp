// SPDX-License-Identifier: Apache-2.0
#pragma once
// The χ² gate: a measurement that its filter's own model says is nearly impossible is not fused.
//
// Against a prediction N(x, P) of the object, a measurement N(z, R) of view u has the innovation
//     ν = z − x (with registration: minus the view's offset, joint_registration.hpp),
//     S = P + μ_u R (+ the offset's share),     d² = νᵀ S⁻¹ ν ~ χ²(3) when the model is right,
// where μ_u ≥ 1 is the view's noise scale (view_noise_scales.hpp; 1 for a view that behaves). The
// measurement passes when d² ≤ γ, γ the χ²(3) quantile of `probability` (default 0.999: γ = 16.27,
// so an honest filter leaves out one good measurement in a thousand; a gross error of a few σ never
// gets in). A measurement that does not pass is counted per view and its row's estimate is the
// object's estimate from the other measurements (or the prediction); nothing is silently dropped.
//
// Measurements are checked against a prediction from one history position or more (with one, the
// velocity is unknown and the prediction's covariance says so). Without such a prediction (an
// object's first time, or `wls`, which has none), the measurements of one object at one time are
// checked against each other: i and j agree when
//     (z_i − z_j)ᵀ (R_i + R_j)⁻¹ (z_i − z_j) ≤ γ.
// The anchor is the measurement that agrees with the most others (the first of those in the given
// order on a tie); the measurements that agree with it pass, the others do not. When no two agree,
// nothing tells the faulty from the good: all pass, and the decision says they conflict. Their
// information-weighted mean would then sit near the most precise of them with the covariance of
// agreeing measurements, however far off the others are; the filter widens it by their spread
// (scene_filter.hpp) and learns nothing about the views from them.
//
// The prediction itself may be what is wrong (a track started from a gross error, a motion the model
// did not foresee). The track starts again from the measurements' consensus (counted as a restart) at
// once when the consensus fails against the prediction and holds more measurements than pass against
// it; and when every measurement fails but no two agree (one view), once that has happened at
// `restart_after` consecutive times (kGatedEventsBeforeRestart for a track whose velocity is known, 1
// for a younger one); until then they are all left out.

#include <cstddef>
#include <span>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

// Off by default: on data unlike what the motion model was trained on, its Q can understate the
// prediction's error until the online Q scale has learnt it, and the gate then leaves out good
// measurements (design §1.12).
struct GateOptions {
  bool enabled = false;
  double probability = 0.999;  // of χ²(3) inside the gate, in (0, 1)
};

inline constexpr int kGatedEventsBeforeRestart = 3;

// The quantile of χ² with 3 degrees of freedom (CDF erf(√(x/2)) − √(2x/π) e^{−x/2}, by bisection).
double chi_square_3_quantile(double probability);

class MeasurementGate {
 public:
  // Throws std::invalid_argument for a probability outside (0, 1).
  explicit MeasurementGate(const GateOptions& options);

  bool enabled() const { return enabled_; }
  double threshold() const { return threshold_; }  // γ
  double probability() const { return probability_; }
  bool passes(double distance_squared) const { return !enabled_ || distance_squared <= threshold_; }

  // Which of one object's measurements at one time pass by mutual agreement (all when disabled), and
  // the anchor (index into `measurements`). `measurements` must not be empty.
  struct Consensus {
    std::size_t anchor = 0;
    std::vector<bool> passes;
    bool agreement = false;  // two of them agree
  };
  Consensus consensus(std::span<const Gaussian3> measurements) const;

  // Which of one object's measurements at one time are fused, as above. `prediction_distances`: d²
  // of each against the prediction, or empty when there is no prediction to check against. `alone`:
  // each measurement with its whole covariance, for the consensus. `gated_events`: the consecutive
  // earlier times at which all failed against the prediction; `restart_after`: how many such times in a
  // row (this one included) start the track again.
  struct Decision {
    std::vector<bool> passes;
    bool restart = false;  // the track starts again from the passing ones
    std::size_t anchor = 0;  // with restart, or without a prediction: the measurement to start from
    bool checked = false;    // a check was made (a prediction, or two measurements or more)
    bool conflicting = false;  // no prediction, two measurements or more, and no two of them agree
  };
  Decision decide(std::span<const double> prediction_distances, std::span<const Gaussian3> alone,
                  int gated_events, int restart_after = kGatedEventsBeforeRestart) const;
  // What decide() gives without the gate: all `count` pass, nothing checked.
  static Decision pass_all(std::size_t count) { return Decision{std::vector<bool>(count, true), false, 0, false, false}; }

 private:
  bool enabled_;
  double probability_;
  double threshold_;
};

// νᵀ S⁻¹ ν (∞ when S is not positive definite).
double distance_squared(const Vector3d& innovation, const Matrix3d& covariance);

}  // namespace stgf
