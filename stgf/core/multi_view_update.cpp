// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/multi_view_update.hpp"

#include <stdexcept>

namespace stgf {

Gaussian3 InformationSum::solve() const {
  if (count_ == 0) throw std::logic_error("InformationSum::solve: nothing to fuse");
  // P̂ = Λ⁻¹ and x̂ = P̂ η from one Cholesky factorisation of Λ.
  return Gaussian3::from_information(information_vector_, information_);
}

Gaussian3 multi_view_update(const Gaussian3& prior, std::span<const Gaussian3> measurements) {
  if (measurements.empty()) return prior;
  InformationSum sum;
  sum.add(prior);
  for (const Gaussian3& measurement : measurements) sum.add(measurement);
  return sum.solve();
}

Gaussian3 information_weighted_mean(std::span<const Gaussian3> measurements) {
  if (measurements.empty()) throw std::invalid_argument("information_weighted_mean: no measurement");
  InformationSum sum;
  for (const Gaussian3& measurement : measurements) sum.add(measurement);
  return sum.solve();
}

MultiViewGains multi_view_gains(const Gaussian3& prior, std::span<const Gaussian3> measurements) {
  const Matrix3d posterior_covariance = multi_view_update(prior, measurements).covariance();
  MultiViewGains gains;
  gains.state_gain = posterior_covariance * prior.information();
  gains.measurement_gains.reserve(measurements.size());
  for (const Gaussian3& measurement : measurements) {
    gains.measurement_gains.push_back(posterior_covariance * measurement.information());
  }
  return gains;
}

}  // namespace stgf
