// SPDX-License-Identifier: Apache-2.0
#include "stgf/learn/filter_calibration.hpp"

#include <algorithm>
#include <stdexcept>

#include "stgf/methods/filter_runner.hpp"

namespace stgf {
namespace {

constexpr double kProcessNoiseFloor = 1e-6;  // m², as in training

struct Residual {
  Vector3d error;             // y − x
  Matrix3d known_covariance;  // P̂_last + P_y
  double dt;
};

std::vector<Residual> filter_residuals(const MotionModel& model, const RegistrationPrior& registration,
                                       std::span<const Measurement> measurements,
                                       std::span<const Vector3d> targets,
                                       std::span<const Matrix3d> target_covariances) {
  std::vector<Residual> residuals;
  FilterOptions options;
  options.registration = registration;
  options.adapt_process_noise = false;
  options.motion_fallback = MotionFallback::kOff;  // Q of the motion model itself
  options.adapt_registration_prior = false;  // the prior as calibrated on this split
  options.gate.enabled = false;  // Q is what the gate is measured with: calibrate it on every residual
  const FilterRun run = run_spatiotemporal_graph_filter(model, options, measurements, /*keep_predictions=*/true);
  // In the order of the rows (the scenes' order would do as well; this one is simpler to state).
  for (std::size_t row = 0; row < measurements.size(); ++row) {
    const auto& prediction = run.predictions[row];
    if (!prediction || prediction->history_positions < 2 || !(prediction->interval > 0.0)) continue;
    const Matrix3d known = target_covariances.empty()
                               ? prediction->state_covariance
                               : Matrix3d(prediction->state_covariance + target_covariances[row]);
    residuals.push_back({targets[row] - prediction->prior.mean(), known, prediction->interval});
  }
  return residuals;
}

}  // namespace

FilterCalibration calibrate_filter_process_noise(MotionModel& model, const RegistrationPrior& registration,
                                                 std::span<const Measurement> measurements,
                                                 std::span<const Vector3d> targets,
                                                 std::span<const Matrix3d> target_covariances, int rounds,
                                                 bool any_heading) {
  if (rounds < 1) throw std::invalid_argument("calibrate_filter_process_noise: rounds must be at least 1");
  if (measurements.size() != targets.size() ||
      (!target_covariances.empty() && target_covariances.size() != targets.size())) {
    throw std::invalid_argument(
        "calibrate_filter_process_noise: one target position (and covariance) per measurement");
  }
  FilterCalibration calibration;
  for (int round = 0; round < rounds; ++round) {
    const std::vector<Residual> residuals =
        filter_residuals(model, registration, measurements, targets, target_covariances);
    if (residuals.empty()) throw std::invalid_argument("no prediction from a track of two or more positions to calibrate Q on");
    if (round == 0) {
      std::vector<double> intervals;
      intervals.reserve(residuals.size());
      for (const Residual& residual : residuals) intervals.push_back(residual.dt);
      std::nth_element(intervals.begin(), intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2),
                       intervals.end());
      calibration.period = intervals[intervals.size() / 2];
      calibration.predictions = residuals.size();
    }
    FilterCalibrationRound report;
    Matrix3d moment = Matrix3d::Zero();
    for (const Residual& residual : residuals) {
      const Matrix3d covariance = residual.known_covariance + model.process_noise(residual.dt);
      report.prior_nees += residual.error.dot(covariance.ldlt().solve(residual.error));
      report.prior_error += residual.error.norm();
      const double scale = (calibration.period / residual.dt) * (calibration.period / residual.dt);
      moment += scale * (residual.error * residual.error.transpose() - residual.known_covariance);
    }
    const auto n = static_cast<double>(residuals.size());
    report.prior_nees /= n;
    report.prior_error /= n;
    const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(symmetrised(moment / n));
    const Vector3d floored = eigen.eigenvalues().cwiseMax(kProcessNoiseFloor);
    Matrix3d measured = eigen.eigenvectors() * floored.asDiagonal() * eigen.eigenvectors().transpose();
    if (any_heading) measured = averaged_over_headings(measured);
    // Damped: Q moves half way, since the residuals it is measured from respond to Q.
    const Matrix3d previous = round == 0 ? measured : model.process_noise(calibration.period);
    report.process_noise = symmetrised(0.5 * (previous + measured));
    model.set_process_noise(report.process_noise, calibration.period);
    calibration.rounds.push_back(report);
  }
  return calibration;
}

}  // namespace stgf
