// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/frame_alignment.hpp"

#include <Eigen/Eigenvalues>

namespace stgf {

void FrameAlignment::follow(const Vector3d& displacement, const Matrix3d& covariance) {
  displacement_ += displacement;
  covariance_ += covariance;
}

void FrameAlignment::gather(const Measurement& measurement, double noise_scale) {
  Measurement moved = measurement;
  moved.position = Gaussian3::from_covariance(measurement.position.mean() - displacement_, measurement.position.covariance());
  gathered_.push_back(Gathered{std::move(moved), noise_scale, covariance_});
}

FrameAlignment::Aligned FrameAlignment::aligned() const {
  Aligned aligned;
  aligned.measurements.reserve(gathered_.size());
  aligned.noise_scales.reserve(gathered_.size());
  aligned.covariances.reserve(gathered_.size());
  if (gathered_.empty()) return aligned;
  // C_mid = (C_1 + C_n) / 2 (1 and n the first and last gathered), A_k = |C_k − C_mid|.
  const Matrix3d middle = 0.5 * (gathered_.front().path_covariance + gathered_.back().path_covariance);
  for (const Gathered& gathered : gathered_) {
    // |X| = V |Λ| Vᵀ: positive semidefinite whatever the order of C_k and C_mid.
    const Eigen::SelfAdjointEigenSolver<Matrix3d> difference(symmetrised(gathered.path_covariance - middle));
    const Matrix3d absolute =
        difference.eigenvectors() * difference.eigenvalues().cwiseAbs().asDiagonal() * difference.eigenvectors().transpose();
    aligned.measurements.push_back(gathered.measurement);
    aligned.noise_scales.push_back(gathered.noise_scale);
    aligned.covariances.push_back(symmetrised(absolute));
  }
  return aligned;
}

}  // namespace stgf
