// SPDX-License-Identifier: Apache-2.0
#pragma once
// Calibrating Q in the regime the filter runs in (DESIGN §1.2).
//
// Training calibrates Q from Φ's residuals on the validation histories as given (fused measurements,
// or truth plus matched noise). Inside the filter Φ reads its own fused estimates instead: each point
// is more accurate, but the errors are correlated in time (every estimate carries part of the
// previous prediction), and Φ predicts worse from them — on mpl, prior DE 0.11 m inside the filter
// against 0.06 m on the validation histories, with NEES of the prior 7.5 instead of 3. So Q is
// calibrated again by running the filter itself on the validation split:
//     r = y − x                          (truth minus Φ's prediction, before the update)
//     Q_ref = E[(Δt_ref / Δt)² (r rᵀ − P̂_last − P_y)]     (eigenvalues floored at 1e-6 m²)
// over the predictions from tracks of at least two positions, Δt_ref their median interval. A new Q
// changes how much the filter trusts Φ and so the histories Φ reads, and a full step can overshoot
// (on mpl the vertical part swung between 2e-4 and 3e-6 m²): after the first round, each round moves
// Q half way to what it measured, Q ← (Q + Q_measured) / 2, a fixed number of rounds. A round whose
// filter ran away is not used, and the next runs half way back to the last Q the filter was stable
// with; the Q left after the rounds is checked by one more run (learn/process_noise_rounds.hpp).
//
// Without truth, y is what was measured at the row's time — the fused position of all views'
// measurements of the object then, with covariance P_y (0 for the truth). Its noise is in r and P_y
// takes it out again; the part of it the registration prior describes (offsets shared with the
// track's own history) largely cancels in r, since the track was built from the same views.

#include <span>
#include <vector>

#include "stgf/core/records.hpp"
#include "stgf/core/view_registration.hpp"
#include "stgf/learn/motion_model.hpp"

namespace stgf {

struct FilterCalibrationRound {
  double prior_nees = 0.0;   // mean NEES of the predictions (x, P̂_last + Q) under the round's Q
  double prior_error = 0.0;  // mean ‖r‖ (m)
  bool stable = true;        // false: the filter ran away under the round's Q (process_noise_rounds.hpp)
  Matrix3d process_noise = Matrix3d::Zero();  // Q_ref for the next round: calibrated, or stepped back
};

struct FilterCalibration {
  std::vector<FilterCalibrationRound> rounds;
  // The run with the last round's Q; not stable: the model was given the last stable round's Q instead
  // (in process_noise).
  FilterCalibrationRound check;
  double period = 0.0;           // Δt_ref
  std::size_t predictions = 0;   // per round
};

// Runs the filter `rounds` times over `measurements` (targets[k] the true position of row k, or the
// measured one with covariance target_covariances[k]; empty covariances: the truth) and leaves
// the last round's Q in `model` (or, when the check run diverged, the last stable one: check); with `any_heading`, Q averaged over the world frame's headings
// (averaged_over_headings). std::invalid_argument when no prediction has two positions behind it.
FilterCalibration calibrate_filter_process_noise(MotionModel& model, const RegistrationPrior& registration,
                                                 std::span<const Measurement> measurements,
                                                 std::span<const Vector3d> targets,
                                                 std::span<const Matrix3d> target_covariances = {},
                                                 int rounds = 5, bool any_heading = false);

// Q at longer intervals (core/process_noise_curve.hpp), after Q_ref: the same split thinned out to
// every s-th frame of each scene (frames counted in Δt_ref from the scene's first time), for strides
// s = 2, 3, 4, 6, 8, 11, … until s Δt_ref reaches `longest` seconds, while the thinned split still has
// kMinimumIntervalPredictions predictions from tracks of two or more positions at about s Δt_ref
// (within 25 %). At each, the filter runs as it would at a frame rate s times lower. Φ forecasts up to
// kCoastingStartFactor times the longest interval it trained on (with histories spaced wider it does
// worse than constant velocity: design §1.9), and only while it predicts better than constant
// velocity: at each such interval the filter also runs with every track coasting by constant velocity
// under the same Q, and from the first interval where that has the smaller mean error ‖r‖ on, the
// tracks coast by constant velocity (up to twice the last interval calibrated; the model's
// widest_history_spacing() then ends between Φ's last node and the coasting curve's first). Each
// interval gives a node of the curve its predictions followed, Φ's or the coasting one:
//     Q_s = Q_prev + ⌊E[(sΔt_ref/Δt)² (r rᵀ − P̂_last − P_y)] − Q_prev⌋₊
// (⌊·⌋₊: negative eigenvalues set to 0, so that Q never shrinks with the interval along a curve;
// Q_prev the curve's node before, Q_ref for Φ's first, none for the coasting curve's first), in two
// rounds, the second moving Q_s half way as Q_ref's rounds do. When the second round's run ran away
// (process_noise_rounds.hpp: its mean error more than kDivergenceFactor times the first's), the
// curves end before τ. The nodes are left in `model`. A model without coasting nodes keeps Φ's horizon
// and no track coasts.
struct IntervalCalibration {
  double interval = 0.0;       // s Δt_ref
  int stride = 0;
  bool coasting = false;       // a node of the coasting curve (constant velocity), else of Φ's
  std::size_t predictions = 0;
  double prior_nees = 0.0;     // of the predictions at this interval, under Q before this node
  double prior_error = 0.0;    // mean ‖r‖ (m)
  // Where Φ and constant velocity were both run at this interval (under the same Q): the mean ‖r‖ of
  // the one not chosen; 0 where only one was run.
  double rival_error = 0.0;
  Matrix3d process_noise = Matrix3d::Zero();
};
struct IntervalCalibrations {
  std::vector<IntervalCalibration> nodes;
  double diverged_at = 0.0;  // the interval whose run ran away, where the curves end; 0: none did
};
inline constexpr std::size_t kMinimumIntervalPredictions = 200;
IntervalCalibrations calibrate_process_noise_intervals(MotionModel& model, const RegistrationPrior& registration,
                                                       std::span<const Measurement> measurements,
                                                       std::span<const Vector3d> targets,
                                                       std::span<const Matrix3d> target_covariances, double longest,
                                                       bool any_heading = false);

}  // namespace stgf
