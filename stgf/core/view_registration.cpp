// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/view_registration.hpp"

#include <cmath>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace stgf {
using Matrix36 = OffsetJacobian;

Matrix36 offset_jacobian(const Matrix3d& measurement_covariance) {
  // [I₃ L 0], L the Cholesky factor of R, written out (called for every measurement, several times), in
  // the order of operations of Eigen's LLT, which it replaces: the same bits.
  const Matrix3d& a = measurement_covariance;
  const double l00 = std::sqrt(a(0, 0));
  const double l10 = a(1, 0) / l00;
  const double l20 = a(2, 0) / l00;
  const double l11 = std::sqrt(a(1, 1) - l10 * l10);
  const double l21 = (a(2, 1) - l20 * l10) / l11;
  const double l22 = std::sqrt(a(2, 2) - (l20 * l20 + l21 * l21));
  Matrix36 jacobian;
  jacobian << 1, 0, 0, l00, 0, 0, 0,  //
      0, 1, 0, l10, l11, 0, 0,        //
      0, 0, 1, l20, l21, l22, 0;
  return jacobian;
}

Matrix36 offset_jacobian(const Measurement& measurement) {
  const Matrix3d& r = measurement.position.covariance();
  if (!measurement.sensor_position) return offset_jacobian(r);
  // F = G L(Gᵀ R G): the Cholesky factor in the frame whose x runs along the ray's heading.
  const Vector3d ray = measurement.position.mean() - *measurement.sensor_position;
  const double length = std::hypot(ray.x(), ray.y());
  if (!(length > 0.0)) return offset_jacobian(r);  // straight above or below the sensor: no heading
  const double c = ray.x() / length;
  const double s = ray.y() / length;
  Matrix3d turn;
  turn << c, -s, 0, s, c, 0, 0, 0, 1;
  Matrix36 jacobian = offset_jacobian(Matrix3d(turn.transpose() * r * turn));
  jacobian.middleCols<3>(3) = turn * jacobian.middleCols<3>(3);
  jacobian.col(6) = Vector3d(ray.x(), ray.y(), 0.0);  // ε's: the horizontal range from the sensor
  return jacobian;
}

OffsetJacobian offset_jacobian(const Measurement& measurement, const Vector3d& position) {
  OffsetJacobian jacobian = offset_jacobian(measurement);
  if (!measurement.sensor_position) return jacobian;
  const Vector3d& sensor = *measurement.sensor_position;
  jacobian.col(6) = Vector3d(position.x() - sensor.x(), position.y() - sensor.y(), 0.0);
  return jacobian;
}

OffsetMatrix RegistrationPrior::covariance() const {
  for (int axis = 0; axis < 3; ++axis) {
    const double sigma = translation_sigma[axis];
    if (!std::isfinite(sigma) || sigma < 0.0) {
      throw std::invalid_argument("registration translation sigma must be finite and >= 0");
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(noise_ratio[axis]) || noise_ratio[axis] < 0.0) {
      throw std::invalid_argument("registration noise ratio must be finite and >= 0");
    }
  }
  if (!std::isfinite(range_scale_sigma) || range_scale_sigma < 0.0) {
    throw std::invalid_argument("registration range scale sigma must be finite and >= 0");
  }
  OffsetMatrix covariance = OffsetMatrix::Zero();
  covariance.diagonal().head<3>() = translation_sigma.cwiseProduct(translation_sigma);
  covariance.diagonal().segment<3>(3) = noise_ratio.cwiseProduct(noise_ratio);
  covariance(6, 6) = range_scale_sigma * range_scale_sigma;
  return covariance;
}

ViewRegistration::ViewRegistration(const RegistrationPrior& prior)
    : prior_(prior), prior_covariance_(prior.covariance()) {}

int ViewRegistration::index_of(std::string_view view) const {
  const auto found = views_.find(view);
  return found == views_.end() ? -1 : found->second;
}

int ViewRegistration::add_view(std::string_view view) {
  const int known = index_of(view);
  if (known >= 0) return known;
  const int index = static_cast<int>(views_.size());
  views_.emplace(std::string(view), index);
  const Eigen::Index size = kOffsetSize * (index + 1);
  offsets_.conservativeResize(size);
  offsets_.tail<kOffsetSize>().setZero();
  Eigen::MatrixXd grown = Eigen::MatrixXd::Zero(size, size);
  grown.topLeftCorner(size - kOffsetSize, size - kOffsetSize) = covariance_;
  grown.bottomRightCorner<kOffsetSize, kOffsetSize>() = prior_covariance_;
  covariance_ = std::move(grown);
  return index;
}

OffsetVector ViewRegistration::offset(std::string_view view) const {
  const int index = index_of(view);
  if (index < 0) return OffsetVector::Zero();
  return offsets_.segment<kOffsetSize>(kOffsetSize * index);
}

OffsetMatrix ViewRegistration::offset_covariance(std::string_view view) const {
  const int index = index_of(view);
  if (index < 0) return prior_covariance_;
  return covariance_.block<kOffsetSize, kOffsetSize>(kOffsetSize * index, kOffsetSize * index);
}

namespace {

// The information-weighted mean of measurements of one object at one time: where ε's column is taken
// from for each of them (offset_jacobian).
Vector3d weighted_mean(std::span<const Measurement* const> measurements) {
  Matrix3d information = Matrix3d::Zero();
  Vector3d weighted = Vector3d::Zero();
  for (const Measurement* measurement : measurements) {
    information += measurement->position.information();
    weighted += measurement->position.information() * measurement->position.mean();
  }
  return information.llt().solve(weighted);
}

}  // namespace

Gaussian3 ViewRegistration::combine(std::span<const Measurement* const> measurements_of_object) const {
  const auto k = static_cast<Eigen::Index>(measurements_of_object.size());
  if (k == 0) throw std::invalid_argument("ViewRegistration::combine needs at least one measurement");
  std::vector<int> index(static_cast<std::size_t>(k));
  std::vector<Matrix36> jacobian(static_cast<std::size_t>(k));
  Eigen::VectorXd corrected(3 * k);
  const Vector3d mean = weighted_mean(measurements_of_object);
  for (Eigen::Index j = 0; j < k; ++j) {
    const Measurement& measurement = *measurements_of_object[static_cast<std::size_t>(j)];
    index[j] = index_of(measurement.view);
    jacobian[j] = offset_jacobian(measurement, mean);
    corrected.segment<3>(3 * j) = measurement.position.mean();
    if (index[j] >= 0) corrected.segment<3>(3 * j) -= jacobian[j] * offsets_.segment<kOffsetSize>(kOffsetSize * index[j]);
  }
  // C = G Σ_VV Gᵀ + diag(R).
  Eigen::MatrixXd noise(3 * k, 3 * k);
  for (Eigen::Index j = 0; j < k; ++j) {
    for (Eigen::Index l = 0; l <= j; ++l) {
      OffsetMatrix offsets_covariance;
      if (index[j] >= 0 && index[l] >= 0) {
        offsets_covariance = covariance_.block<kOffsetSize, kOffsetSize>(kOffsetSize * index[j], kOffsetSize * index[l]);
      } else if (j == l) {
        offsets_covariance = prior_covariance_;  // an unknown view: its prior, independent of the others
      } else {
        offsets_covariance.setZero();
      }
      Matrix3d block = jacobian[j] * offsets_covariance * jacobian[l].transpose();
      if (j == l) block += measurements_of_object[static_cast<std::size_t>(j)]->position.covariance();
      noise.block<3, 3>(3 * j, 3 * l) = block;
      noise.block<3, 3>(3 * l, 3 * j) = block.transpose();
    }
  }
  // A = Sᵀ C⁻¹ S, η = Sᵀ C⁻¹ c.
  const Eigen::LLT<Eigen::MatrixXd> factor(noise);
  if (factor.info() != Eigen::Success) throw std::runtime_error("registration: measurement covariance not positive definite");
  const Eigen::MatrixXd stacked_identity = Eigen::MatrixXd::Identity(3, 3).replicate(k, 1);
  const Eigen::MatrixXd weights = factor.solve(stacked_identity);  // C⁻¹ S
  Matrix3d information = stacked_identity.transpose() * weights;
  const Vector3d information_vector = weights.transpose() * corrected;
  return Gaussian3::from_information(information_vector, symmetrised(information));
}

void ViewRegistration::learn(std::span<const Measurement* const> step) {
  if (prior_.is_zero()) return;  // nothing to estimate: every offset is exactly zero
  // Objects in order of first appearance (a fixed order keeps the result bit-reproducible).
  std::vector<std::string_view> objects;
  std::map<std::string_view, std::vector<const Measurement*>> of_object;
  for (const Measurement* measurement : step) {
    add_view(measurement->view);
    auto& rows = of_object[measurement->object];
    if (rows.empty()) objects.push_back(measurement->object);
    rows.push_back(measurement);
  }
  for (const std::string_view object : objects) {
    const std::vector<const Measurement*>& rows = of_object.at(object);
    const auto k = static_cast<Eigen::Index>(rows.size());
    if (k < 2) continue;  // one view alone says nothing about offsets
    // d_j = z_j − z_0 = H_j β_j − H_0 β_0 + e_j − e_0, j = 1..k−1; only the involved views' columns.
    const Eigen::Index m = 3 * (k - 1);
    std::vector<Eigen::Index> column(static_cast<std::size_t>(k));
    std::vector<Matrix36> jacobian(static_cast<std::size_t>(k));
    const Vector3d mean = weighted_mean(rows);
    for (Eigen::Index j = 0; j < k; ++j) {
      column[j] = kOffsetSize * index_of(rows[j]->view);
      jacobian[j] = offset_jacobian(*rows[j], mean);
    }
    Eigen::MatrixXd observation = Eigen::MatrixXd::Zero(m, kOffsetSize * k);  // H_obs on the involved columns
    Eigen::VectorXd innovation(m);
    Eigen::MatrixXd noise(m, m);
    const Matrix3d& first_noise = rows[0]->position.covariance();
    for (Eigen::Index j = 1; j < k; ++j) {
      const Eigen::Index r = 3 * (j - 1);
      observation.block<3, kOffsetSize>(r, 0) = -jacobian[0];
      observation.block<3, kOffsetSize>(r, kOffsetSize * j) = jacobian[j];
      innovation.segment<3>(r) = rows[j]->position.mean() - rows[0]->position.mean() -
                                 jacobian[j] * offsets_.segment<kOffsetSize>(column[j]) +
                                 jacobian[0] * offsets_.segment<kOffsetSize>(column[0]);
      for (Eigen::Index l = 1; l < k; ++l) {
        noise.block<3, 3>(r, 3 * (l - 1)) = first_noise;
        if (l == j) noise.block<3, 3>(r, 3 * (l - 1)) += rows[j]->position.covariance();
      }
    }
    // Σ H_obsᵀ (all views' rows) and H_obs Σ H_obsᵀ + N.
    Eigen::MatrixXd cross(covariance_.rows(), m);  // Σ H_obsᵀ
    cross.setZero();
    for (Eigen::Index j = 0; j < k; ++j) {
      cross.noalias() += covariance_.middleCols<kOffsetSize>(column[j]) *
                         observation.middleCols<kOffsetSize>(kOffsetSize * j).transpose();
    }
    Eigen::MatrixXd innovation_covariance = noise;
    for (Eigen::Index j = 0; j < k; ++j) {
      innovation_covariance.noalias() += observation.middleCols<kOffsetSize>(kOffsetSize * j) *
                                         cross.middleRows<kOffsetSize>(column[j]);
    }
    innovation_covariance = 0.5 * (innovation_covariance + innovation_covariance.transpose());
    const Eigen::LLT<Eigen::MatrixXd> factor(innovation_covariance);
    if (factor.info() != Eigen::Success) continue;  // cannot happen with R positive definite
    const Eigen::MatrixXd gain_transposed = factor.solve(cross.transpose());  // Kᵀ = S⁻¹ (Σ Hᵀ)ᵀ
    offsets_.noalias() += gain_transposed.transpose() * innovation;
    covariance_.noalias() -= cross * gain_transposed;  // Σ − K S Kᵀ = Σ − (ΣHᵀ) S⁻¹ (ΣHᵀ)ᵀ
    covariance_ = 0.5 * (covariance_ + covariance_.transpose());
  }
}

}  // namespace stgf
