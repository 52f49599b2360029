// SPDX-License-Identifier: Apache-2.0
#pragma once
// The rounds of Q's calibration in the filter (filter_calibration.hpp), guarded against divergence.
//
// Each round runs the filter with a Q and measures the Q its prediction residuals call for. The
// measured Q responds to the Q the filter ran with: a smaller Q makes the filter trust Φ more, and
// Φ, reading histories made of its own earlier predictions, may then run away. The state is the
// position alone, so P does not hold the velocity the history implies: an error in the last estimates
// enters Φ's next prediction amplified (a constant-velocity prediction doubles it), and when the
// update pulls back too little, the error grows from step to step. Seen on cad with 5 s validation
// scenes: Q_y fell from 0.118 to 0.018 m² in the first round, the next round's mean prediction error
// was 202 m (from 0.51 m), and that round's residuals asked for Q = 10⁷ m².
//
// So a round is *diverged* when its mean prediction error is not finite or more than
// kDivergenceFactor times the smallest of the stable rounds before it. Its measurement is thrown away,
// and the next round runs half way back to the Q of the last stable round (a line search along the
// step). A stable round moves Q as before:
//     round 0:  Q ← Q_measured
//     later:    Q ← (Q + Q_measured) / 2       (damped: the residuals respond to Q)
// The first round has nothing to compare with: it is always stable unless its error is not finite.
// When it was the one that ran away (the trained Q far too small), a later round's error is less than
// 1/kDivergenceFactor of it: that round starts the rounds afresh (it is the new reference, and Q takes
// what it measured), instead of halving a Q of 10⁷ m² round by round.
// After the last round, the Q left has not been run; the caller checks it with one more run (check()),
// which falls back to the last stable Q when that run diverges.

#include "stgf/core/gaussian.hpp"

namespace stgf {

inline constexpr double kDivergenceFactor = 2.0;

// A run whose mean prediction error is `error` ran away from one whose error was `reference`.
inline bool ran_away(double error, double reference) {
  return !(error <= kDivergenceFactor * reference);  // true for a NaN too
}

class ProcessNoiseRounds {
 public:
  // `initial`: the Q of the first round's run.
  explicit ProcessNoiseRounds(const Matrix3d& initial) : current_(initial), stable_(initial) {}

  // The Q the next run uses.
  const Matrix3d& current() const { return current_; }

  // A run with current() had mean prediction error `error` and its residuals measured `measured`.
  // Returns false when the run diverged (the measurement is then not used). Throws
  // std::runtime_error when the first round's error is not finite.
  bool record(double error, const Matrix3d& measured);

  // The run with the final current() had mean prediction error `error`: when it diverged, current()
  // becomes the last stable Q. Returns whether it was stable.
  bool check(double error);

  bool diverged(double error) const;

 private:
  Matrix3d current_;
  Matrix3d stable_;            // the Q of the last round whose run was stable
  double best_error_ = -1.0;   // the smallest mean error of a stable run; negative before the first
};

}  // namespace stgf
