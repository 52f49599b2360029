// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/constant_velocity_filter.hpp"

#include <cmath>
#include <stdexcept>

#include "stgf/core/cholesky3.hpp"
#include "stgf/core/multi_view_update.hpp"

namespace stgf {

ConstantVelocityFilter::ConstantVelocityFilter(const ConstantVelocityModel& model,
                                               const Gaussian3& first_measurement)
    : model_(model) {
  state_ << first_measurement.mean(), Vector3d::Zero();
  covariance_.setZero();
  covariance_.topLeftCorner<3, 3>().diagonal().setConstant(model.initial_position_variance);
  covariance_.bottomRightCorner<3, 3>().diagonal().setConstant(model.initial_velocity_variance);
}

void ConstantVelocityFilter::predict(double dt) {
  if (!(dt >= 0.0) || !std::isfinite(dt)) {
    throw std::invalid_argument("ConstantVelocityFilter::predict: step must be finite and >= 0");
  }
  // s ← F s with F = [I Δt·I; 0 I].
  state_.head<3>() += dt * state_.tail<3>();
  // C ← F C Fᵀ, written out per 3×3 block: [A B; Bᵀ D] ↦ [A + Δt(B + Bᵀ) + Δt² D, B + Δt D; ·, D].
  const Matrix3d a = covariance_.topLeftCorner<3, 3>();
  const Matrix3d b = covariance_.topRightCorner<3, 3>();
  const Matrix3d d = covariance_.bottomRightCorner<3, 3>();
  covariance_.topLeftCorner<3, 3>() = a + dt * (b + b.transpose()) + dt * dt * d;
  covariance_.topRightCorner<3, 3>() = b + dt * d;
  covariance_.bottomLeftCorner<3, 3>() = (b + dt * d).transpose();
  // + Q(Δt).
  covariance_.topLeftCorner<3, 3>().diagonal().array() += model_.position_noise_density * dt;
  covariance_.bottomRightCorner<3, 3>().diagonal().array() += model_.velocity_noise_density * dt;
}

void ConstantVelocityFilter::update(const Gaussian3& measurement) {
  // With H = [I 0]: H C Hᵀ = A (position block), C Hᵀ = first three columns of C.
  const Eigen::Matrix<double, 6, 3> c_ht = covariance_.leftCols<3>();
  const Matrix3d innovation_covariance = covariance_.topLeftCorner<3, 3>() + measurement.covariance();
  const Cholesky3 cholesky(innovation_covariance);
  if (!cholesky.ok()) {
    throw std::runtime_error("ConstantVelocityFilter::update: innovation covariance not SPD");
  }
  // K = C Hᵀ S⁻¹ with S⁻¹ from the Cholesky factorisation of S.
  const Eigen::Matrix<double, 6, 3> gain = c_ht * cholesky.inverse();
  state_ += gain * (measurement.mean() - state_.head<3>());
  Matrix6d i_minus_kh = Matrix6d::Identity();
  i_minus_kh.leftCols<3>() -= gain;
  const Matrix6d joseph = i_minus_kh * covariance_ * i_minus_kh.transpose() +
                          gain * measurement.covariance() * gain.transpose();
  covariance_ = 0.5 * (joseph + joseph.transpose());
}

void ConstantVelocityFilter::update(std::span<const Gaussian3> measurements) {
  if (measurements.empty()) return;
  update(information_weighted_mean(measurements));
}

Gaussian3 ConstantVelocityFilter::position() const {
  return Gaussian3::from_covariance(state_.head<3>(), covariance_.topLeftCorner<3, 3>());
}

}  // namespace stgf
