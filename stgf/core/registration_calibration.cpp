// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/registration_calibration.hpp"

#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace stgf {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Parameters = std::array<double, 4>;  // log10 of σ_x, σ_y, σ_z, α

struct GroupStatistics {
  Matrix6d a = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
};

constexpr double kLowest = -4.0;                            // log10 of the smallest σ or α
constexpr std::array<double, 4> kHighest = {1.5, 1.5, 1.5, 2.0};

double log_likelihood(const std::vector<GroupStatistics>& groups, const Parameters& parameters) {
  Vector6d prior_information;
  for (int axis = 0; axis < 3; ++axis) prior_information[axis] = std::pow(10.0, -2.0 * parameters[axis]);
  prior_information.tail<3>().setConstant(std::pow(10.0, -2.0 * parameters[3]));
  const double log_det_prior = prior_information.array().log().sum();
  double total = 0.0;
  for (const GroupStatistics& group : groups) {
    Matrix6d posterior_information = group.a;
    posterior_information.diagonal() += prior_information;
    const Eigen::LLT<Matrix6d> factor(posterior_information);
    const double log_det = 2.0 * factor.matrixL().toDenseMatrix().diagonal().array().log().sum();
    total -= 0.5 * (-group.b.dot(factor.solve(group.b)) + log_det - log_det_prior);
  }
  return total;
}

// Best value of one coordinate on the grid lo, lo + step, …, hi (others fixed).
double best_on_grid(const std::vector<GroupStatistics>& groups, Parameters parameters, int coordinate, double lo,
                    double hi, double step) {
  double best_value = parameters[coordinate];
  double best = log_likelihood(groups, parameters);
  for (double value = lo; value <= hi + 1e-9; value += step) {
    parameters[coordinate] = value;
    const double candidate = log_likelihood(groups, parameters);
    if (candidate > best) {
      best = candidate;
      best_value = value;
    }
  }
  return best_value;
}

}  // namespace

RegistrationCalibration calibrate_registration_prior(std::span<const Measurement> measurements,
                                                     std::span<const Vector3d> truth) {
  if (measurements.size() != truth.size()) {
    throw std::invalid_argument("calibrate_registration_prior: one truth position per measurement");
  }
  std::map<std::pair<std::string, std::string>, GroupStatistics> by_group;
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    const Measurement& measurement = measurements[k];
    Eigen::Matrix<double, 3, 6> jacobian;
    jacobian.leftCols<3>().setIdentity();
    jacobian.rightCols<3>() = measurement.position.covariance().llt().matrixL();
    const Eigen::Matrix<double, 6, 3> weighted = jacobian.transpose() * measurement.position.information();
    GroupStatistics& group = by_group[{measurement.scene, measurement.view}];
    group.a.noalias() += weighted * jacobian;
    group.b.noalias() += weighted * (measurement.position.mean() - truth[k]);
  }
  std::vector<GroupStatistics> groups;
  groups.reserve(by_group.size());
  for (auto& entry : by_group) groups.push_back(std::move(entry.second));

  RegistrationCalibration result;
  result.groups = groups.size();
  if (groups.empty()) return result;
  Parameters parameters = {kLowest, kLowest, kLowest, kLowest};
  const double none = log_likelihood(groups, parameters);
  for (const double step : {0.1, 0.01}) {
    for (int sweep = 0; sweep < 20; ++sweep) {
      const Parameters before = parameters;
      for (int coordinate = 0; coordinate < 4; ++coordinate) {
        const double lo = step < 0.1 ? std::max(kLowest, parameters[coordinate] - 0.1) : kLowest;
        const double hi = step < 0.1 ? std::min(kHighest[coordinate], parameters[coordinate] + 0.1) : kHighest[coordinate];
        parameters[coordinate] = best_on_grid(groups, parameters, coordinate, lo, hi, step);
      }
      if (parameters == before) break;
    }
  }
  auto sigma = [](double log10_value) { return log10_value <= kLowest + 1e-9 ? 0.0 : std::pow(10.0, log10_value); };
  result.prior.translation_sigma = Vector3d(sigma(parameters[0]), sigma(parameters[1]), sigma(parameters[2]));
  result.prior.noise_ratio = sigma(parameters[3]);
  result.log_likelihood_gain = (log_likelihood(groups, parameters) - none) / static_cast<double>(groups.size());
  return result;
}

}  // namespace stgf
