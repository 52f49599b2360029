// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/motion_choice.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace stgf {

double per_axis_log_likelihood(const Vector3d& innovation, const Matrix3d& known_covariance,
                               const Matrix3d& process_noise, const Vector3d& scales) {
  double total = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double variance = known_covariance(a, a) + scales[a] * process_noise(a, a);
    if (!(variance > 0.0)) continue;  // an axis neither model is uncertain on tells nothing
    total -= 0.5 * (innovation[a] * innovation[a] / variance + std::log(2.0 * std::numbers::pi * variance));
  }
  return total;
}

void MotionChoice::add(const Vector3d& learned_innovation, const Vector3d& fallback_innovation,
                       const Matrix3d& learned_known_covariance, const Matrix3d& fallback_known_covariance,
                       const Matrix3d& process_noise, const ProcessNoiseScale& learned, bool adapt) {
  if (policy_ != MotionFallback::kAuto) throw std::logic_error("MotionChoice::add: only the automatic choice compares");
  evidence_ += per_axis_log_likelihood(fallback_innovation, fallback_known_covariance, process_noise, fallback_scale_.scales()) -
               per_axis_log_likelihood(learned_innovation, learned_known_covariance, process_noise, learned.scales());
  ++samples_;
  if (adapt) fallback_scale_.add(fallback_innovation, fallback_known_covariance, process_noise);
  const bool constant_velocity = constant_velocity_ ? evidence_ > -kSwitchEvidence : evidence_ > kSwitchEvidence;
  if (constant_velocity != constant_velocity_) ++switches_;
  constant_velocity_ = constant_velocity;
}

}  // namespace stgf
