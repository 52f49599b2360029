// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/joint_registration.hpp"

#include <cmath>
#include <stdexcept>

namespace stgf {
using Matrix36 = Eigen::Matrix<double, 3, 6>;

JointRegistration::JointRegistration(const RegistrationPrior& prior)
    : prior_(prior), prior_covariance_(prior.covariance()) {}

Eigen::Index JointRegistration::grow(Eigen::Index size) {
  const Eigen::Index start = mean_.size();
  mean_.conservativeResize(start + size);
  mean_.tail(size).setZero();
  covariance_.conservativeResize(start + size, start + size);
  covariance_.rightCols(size).setZero();
  covariance_.bottomRows(size).setZero();
  return start;
}

Eigen::Index JointRegistration::view_index(std::string_view view) const {
  const auto found = views_.find(view);
  return found == views_.end() ? -1 : found->second;
}

Eigen::Index JointRegistration::add_view(std::string_view view) {
  if (prior_.is_zero()) return -1;
  if (const Eigen::Index known = view_index(view); known >= 0) return known;
  const Eigen::Index start = grow(6);
  covariance_.block<6, 6>(start, start) = prior_covariance_;
  views_.emplace(std::string(view), start);
  return start;
}

void JointRegistration::add_object(const Measurement& first, double noise_scale) {
  if (has_object(first.object)) throw std::logic_error("JointRegistration::add_object: object already known");
  const Eigen::Index u = add_view(first.view);
  const Matrix3d& r = first.position.covariance();
  Vector3d mean = first.position.mean();
  Matrix3d covariance = noise_scale * r;
  Eigen::MatrixXd cross;  // Σ_{i,·} = −H_u Σ_{u,·}
  if (u >= 0) {
    const Matrix36 h = offset_jacobian(r);
    mean -= h * mean_.segment<6>(u);
    cross = -h * covariance_.middleRows<6>(u);
    covariance += h * covariance_.block<6, 6>(u, u) * h.transpose();
  }
  const Eigen::Index i = grow(3);
  mean_.segment<3>(i) = mean;
  if (u >= 0) {
    covariance_.block(i, 0, 3, i) = cross;
    covariance_.block(0, i, i, 3) = cross.transpose();
  }
  covariance_.block<3, 3>(i, i) = symmetrised(covariance);
  objects_.emplace(first.object, i);
}

void JointRegistration::remove_object(std::string_view object) {
  const auto found = objects_.find(object);
  if (found == objects_.end()) return;
  const Eigen::Index i = found->second;
  const Eigen::Index size = mean_.size();
  const Eigen::Index after = size - i - 3;
  Eigen::VectorXd mean(size - 3);
  mean << mean_.head(i), mean_.tail(after);
  Eigen::MatrixXd covariance(size - 3, size - 3);
  covariance.topLeftCorner(i, i) = covariance_.topLeftCorner(i, i);
  covariance.topRightCorner(i, after) = covariance_.topRightCorner(i, after);
  covariance.bottomLeftCorner(after, i) = covariance_.bottomLeftCorner(after, i);
  covariance.bottomRightCorner(after, after) = covariance_.bottomRightCorner(after, after);
  mean_ = std::move(mean);
  covariance_ = std::move(covariance);
  objects_.erase(found);
  for (auto* blocks : {&objects_, &views_}) {
    for (auto& [name, start] : *blocks) {
      if (start > i) start -= 3;
    }
  }
}

void JointRegistration::predict(std::string_view object, const Vector3d& displacement, const Matrix3d& process_noise) {
  const Eigen::Index i = objects_.find(object)->second;
  mean_.segment<3>(i) += displacement;
  covariance_.block<3, 3>(i, i) += process_noise;
}

void JointRegistration::release_offset(std::string_view view, const Matrix3d& covariance) {
  const Eigen::Index u = view_index(view);
  if (u < 0) return;
  covariance_.block<3, 3>(u, u) += symmetrised(covariance);
}

JointRegistration::Innovation JointRegistration::innovation(const Measurement& measurement, double noise_scale) const {
  const Eigen::Index i = objects_.find(measurement.object)->second;
  const Eigen::Index u = view_index(measurement.view);
  const Matrix3d& r = measurement.position.covariance();
  Innovation result{measurement.position.mean() - mean_.segment<3>(i), covariance_.block<3, 3>(i, i) + noise_scale * r};
  if (!prior_.is_zero()) {
    const Matrix36 h = offset_jacobian(r);
    if (u < 0) {
      result.covariance += h * prior_covariance_ * h.transpose();
    } else {
      const Matrix3d cross = covariance_.block<3, 6>(i, u) * h.transpose();  // Σ_iu Hᵀ
      result.value -= h * mean_.segment<6>(u);
      result.covariance += h * covariance_.block<6, 6>(u, u) * h.transpose() + cross + cross.transpose();
    }
  }
  result.covariance = symmetrised(result.covariance);
  return result;
}

void JointRegistration::update(const Measurement& measurement, double noise_scale) {
  const auto found = objects_.find(measurement.object);
  if (found == objects_.end()) throw std::logic_error("JointRegistration::update: unknown object");
  const Eigen::Index i = found->second;
  const Eigen::Index u = add_view(measurement.view);
  const Matrix3d& r = measurement.position.covariance();
  // A = Σ Hᵀ (every entry against the measurement), S = H A + R.
  Eigen::MatrixXd a = covariance_.middleCols<3>(i);
  Vector3d innovation = measurement.position.mean() - mean_.segment<3>(i);
  Matrix36 h;
  if (u >= 0) {
    h = offset_jacobian(r);
    a.noalias() += covariance_.middleCols<6>(u) * h.transpose();
    innovation -= h * mean_.segment<6>(u);
  }
  Matrix3d s = a.middleRows<3>(i) + noise_scale * r;
  if (u >= 0) s += h * a.middleRows<6>(u);
  const Eigen::LLT<Matrix3d> factor(symmetrised(s));
  if (factor.info() != Eigen::Success) throw std::runtime_error("registration: innovation covariance not positive definite");
  const Eigen::MatrixXd gain_transposed = factor.solve(a.transpose());  // Kᵀ = S⁻¹ Aᵀ
  mean_.noalias() += gain_transposed.transpose() * innovation;
  covariance_.noalias() -= a * gain_transposed;  // Σ − A S⁻¹ Aᵀ
  covariance_ = 0.5 * (covariance_ + covariance_.transpose()).eval();
}

Gaussian3 JointRegistration::corrected(const Measurement& measurement, double noise_scale) const {
  const Eigen::Index u = view_index(measurement.view);
  const Matrix3d& r = measurement.position.covariance();
  if (prior_.is_zero() && noise_scale == 1.0) return measurement.position;
  if (prior_.is_zero()) return Gaussian3::from_covariance(measurement.position.mean(), noise_scale * r);
  const Matrix36 h = offset_jacobian(r);
  const Eigen::Matrix<double, 6, 1> offset = u < 0 ? Eigen::Matrix<double, 6, 1>::Zero() : Eigen::Matrix<double, 6, 1>(mean_.segment<6>(u));
  const Eigen::Matrix<double, 6, 6> spread = u < 0 ? prior_covariance_ : Eigen::Matrix<double, 6, 6>(covariance_.block<6, 6>(u, u));
  return Gaussian3::from_covariance(measurement.position.mean() - h * offset, noise_scale * r + h * spread * h.transpose());
}

Gaussian3 JointRegistration::position(std::string_view object) const {
  const Eigen::Index i = objects_.find(object)->second;
  return Gaussian3::from_covariance(mean_.segment<3>(i), covariance_.block<3, 3>(i, i));
}

Eigen::Matrix<double, 6, 1> JointRegistration::offset(std::string_view view) const {
  const Eigen::Index u = view_index(view);
  return u < 0 ? Eigen::Matrix<double, 6, 1>::Zero() : Eigen::Matrix<double, 6, 1>(mean_.segment<6>(u));
}

Eigen::Matrix<double, 6, 6> JointRegistration::offset_covariance(std::string_view view) const {
  const Eigen::Index u = view_index(view);
  return u < 0 ? prior_covariance_ : Eigen::Matrix<double, 6, 6>(covariance_.block<6, 6>(u, u));
}

}  // namespace stgf
