// SPDX-License-Identifier: Apache-2.0
#include "stgf/learn/process_noise_rounds.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace stgf {

bool ProcessNoiseRounds::diverged(double error) const {
  return !std::isfinite(error) || (best_error_ >= 0.0 && ran_away(error, best_error_));
}

bool ProcessNoiseRounds::record(double error, const Matrix3d& measured) {
  const bool first = best_error_ < 0.0;
  if (first && !std::isfinite(error)) {
    throw std::runtime_error("the filter's prediction error on the validation split is not finite with the trained Q");
  }
  if (diverged(error)) {
    current_ = symmetrised(0.5 * (stable_ + current_));
    return false;
  }
  // Against this run, the stable rounds before ran away (the first round's Q can be far too small):
  // start afresh from it.
  const bool fresh = first || ran_away(best_error_, error);
  stable_ = current_;
  best_error_ = fresh ? error : std::min(best_error_, error);
  // A fresh start takes what it measured: (Q_measured + Q_measured) / 2, bit for bit.
  const Matrix3d& previous = fresh ? measured : current_;
  current_ = symmetrised(0.5 * (previous + measured));
  return true;
}

bool ProcessNoiseRounds::check(double error) {
  if (!diverged(error)) return true;
  current_ = stable_;
  return false;
}

}  // namespace stgf
