// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/frame_alignment.hpp"

#include <cmath>

#include "stgf/core/eigenvalue_floor.hpp"

namespace stgf {

void FrameAlignment::follow(const Vector3d& displacement, const Matrix3d& covariance) {
  displacement_ += displacement;
  // The path's covariance grows by what the step adds; a prediction's covariance can also take some
  // away (the slope's terms, object_track.hpp: where the forecast reads the position from several
  // history positions it can be more certain than the state), which is the state's share, not the
  // path's. Only the added part is followed, so that C_n − C_1 stays a covariance and every A_k with it
  // (a measurement's noise plus an A_k that is not one was not a covariance either).
  covariance_ += nearest_covariance(covariance);
}

void FrameAlignment::gather(const Measurement& measurement, double noise_scale) {
  if (gathered_.empty()) gathered_.reserve(kTypicalViews);
  Gathered& gathered = gathered_.emplace_back(Gathered{measurement, noise_scale, covariance_});
  gathered.measurement.position = measurement.position.moved_by(-displacement_);
}

void FrameAlignment::aligned(std::vector<const Measurement*>& measurements, std::vector<double>& noise_scales,
                             std::vector<Matrix3d>& covariances) const {
  measurements.clear();
  noise_scales.clear();
  covariances.clear();
  if (gathered_.empty()) return;
  // A_k = |s_k| (C_n − C_1) / 2 with s_k = 2 tr(C_k − C_1) / tr(C_n − C_1) − 1 ∈ [−1, 1].
  const Matrix3d& first = gathered_.front().path_covariance;
  const Matrix3d span = gathered_.back().path_covariance - first;
  const double length = span.trace();
  for (const Gathered& gathered : gathered_) {
    const double position = length > 0.0 ? 2.0 * (gathered.path_covariance - first).trace() / length - 1.0 : 0.0;
    measurements.push_back(&gathered.measurement);
    noise_scales.push_back(gathered.noise_scale);
    covariances.push_back(0.5 * std::abs(position) * span);
  }
}

}  // namespace stgf
