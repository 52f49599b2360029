// SPDX-License-Identifier: Apache-2.0
#include "stgf/learn/filter_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "stgf/core/eigenvalue_floor.hpp"
#include "stgf/core/process_noise_curve.hpp"
#include "stgf/learn/process_noise_rounds.hpp"
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
  options.cross_view_weights = false;  // and with every measurement as its R states, as the split's are
  // Q as the forecasts' whole error beyond the state's, as it was calibrated before the filter counted
  // the history's velocity error apart (object_track.hpp: the calibration's histories are long, and hold little of it).
  options.history_velocity_error = false;
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

// The rows of every s-th frame of each scene, frames counted in `period` from the scene's first time.
struct Thinned {
  std::vector<Measurement> measurements;
  std::vector<Vector3d> targets;
  std::vector<Matrix3d> target_covariances;
};
Thinned thinned(std::span<const Measurement> measurements, std::span<const Vector3d> targets,
                std::span<const Matrix3d> target_covariances, double period, int stride) {
  std::map<std::string_view, double> first_time;
  for (const Measurement& row : measurements) {
    const auto [it, added] = first_time.emplace(row.scene, row.time);
    if (!added) it->second = std::min(it->second, row.time);
  }
  Thinned result;
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    const Measurement& row = measurements[k];
    const long long frame = std::llround((row.time - first_time.at(row.scene)) / period);
    if (frame % stride != 0) continue;
    result.measurements.push_back(row);
    result.targets.push_back(targets[k]);
    if (!target_covariances.empty()) result.target_covariances.push_back(target_covariances[k]);
  }
  return result;
}

// E[(τ/Δt)² (r rᵀ − known)] over the residuals within 25 % of τ, eigenvalues floored at 1e-6 m²
// (averaged over headings with `any_heading`); nullopt with fewer than kMinimumIntervalPredictions.
struct IntervalMoment {
  Matrix3d moment;
  std::size_t count;
  double nees;
  double error;
};
std::optional<IntervalMoment> interval_moment(const std::vector<Residual>& residuals, double tau,
                                              const MotionModel& model, bool coasting, bool any_heading) {
  Matrix3d sum = Matrix3d::Zero();
  IntervalMoment result{Matrix3d::Zero(), 0, 0.0, 0.0};
  for (const Residual& residual : residuals) {
    if (std::abs(residual.dt - tau) > 0.25 * tau) continue;
    const Matrix3d covariance = residual.known_covariance + (coasting ? model.coasting_process_noise(residual.dt)
                                                                        : model.process_noise(residual.dt));
    result.nees += residual.error.dot(covariance.ldlt().solve(residual.error));
    result.error += residual.error.norm();
    const double scale = (tau / residual.dt) * (tau / residual.dt);
    sum += scale * (residual.error * residual.error.transpose() - residual.known_covariance);
    ++result.count;
  }
  if (result.count < kMinimumIntervalPredictions) return std::nullopt;
  const auto n = static_cast<double>(result.count);
  result.nees /= n;
  result.error /= n;
  result.moment = with_eigenvalues_at_least(sum / n, kProcessNoiseFloor);
  if (any_heading) result.moment = averaged_over_headings(result.moment);
  return result;
}

// The mean NEES of the residuals under the model's Q, and their mean ‖r‖ (m).
struct PredictionScore {
  double nees = 0.0;
  double error = 0.0;
};
PredictionScore score(const std::vector<Residual>& residuals, const MotionModel& model) {
  PredictionScore result;
  for (const Residual& residual : residuals) {
    const Matrix3d covariance = residual.known_covariance + model.process_noise(residual.dt);
    result.nees += residual.error.dot(covariance.ldlt().solve(residual.error));
    result.error += residual.error.norm();
  }
  result.nees /= static_cast<double>(residuals.size());
  result.error /= static_cast<double>(residuals.size());
  return result;
}

// One target (and covariance, unless there are none) per measurement.
void check_targets(const char* function, std::span<const Measurement> measurements, std::span<const Vector3d> targets,
                   std::span<const Matrix3d> target_covariances) {
  if (measurements.size() != targets.size() ||
      (!target_covariances.empty() && target_covariances.size() != targets.size())) {
    throw std::invalid_argument(std::string(function) + ": one target position (and covariance) per measurement");
  }
}

// `measured`, raised where it is below `previous`: previous + ⌊measured − previous⌋₊.
Matrix3d at_least(const Matrix3d& measured, const Matrix3d& previous) {
  return symmetrised(previous + with_eigenvalues_at_least(measured - previous, 0.0));
}

}  // namespace

FilterCalibration calibrate_filter_process_noise(MotionModel& model, const RegistrationPrior& registration,
                                                 std::span<const Measurement> measurements,
                                                 std::span<const Vector3d> targets,
                                                 std::span<const Matrix3d> target_covariances, int rounds,
                                                 bool any_heading) {
  if (rounds < 1) throw std::invalid_argument("calibrate_filter_process_noise: rounds must be at least 1");
  check_targets("calibrate_filter_process_noise", measurements, targets, target_covariances);
  FilterCalibration calibration;
  std::optional<ProcessNoiseRounds> steps;  // from the first round on, once Δt_ref is known
  const auto residuals_under_current_q = [&] {
    std::vector<Residual> residuals = filter_residuals(model, registration, measurements, targets, target_covariances);
    if (residuals.empty()) throw std::invalid_argument("no prediction from a track of two or more positions to calibrate Q on");
    return residuals;
  };
  for (int round = 0; round < rounds; ++round) {
    const std::vector<Residual> residuals = residuals_under_current_q();
    if (round == 0) {
      std::vector<double> intervals;
      intervals.reserve(residuals.size());
      for (const Residual& residual : residuals) intervals.push_back(residual.dt);
      std::nth_element(intervals.begin(), intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2),
                       intervals.end());
      calibration.period = intervals[intervals.size() / 2];
      calibration.predictions = residuals.size();
      steps.emplace(model.process_noise(calibration.period));
    }
    // The moment of interval_moment over every residual, written out here: folding the two together
    // moved the last bits of every model's Q.
    const PredictionScore scored = score(residuals, model);
    FilterCalibrationRound report;
    report.prior_nees = scored.nees;
    report.prior_error = scored.error;
    Matrix3d moment = Matrix3d::Zero();
    for (const Residual& residual : residuals) {
      // Q_ref / Q(dt) by the law without nodes.
      moment += reference_shrinkage(calibration.period, residual.dt) * (residual.error * residual.error.transpose() - residual.known_covariance);
    }
    const auto n = static_cast<double>(residuals.size());
    Matrix3d measured = with_eigenvalues_at_least(moment / n, kProcessNoiseFloor);
    if (any_heading) measured = averaged_over_headings(measured);
    report.stable = steps->record(report.prior_error, measured);
    report.process_noise = steps->current();
    model.set_process_noise(report.process_noise, calibration.period);
    calibration.rounds.push_back(report);
  }
  // The Q left has not been run yet.
  const PredictionScore last = score(residuals_under_current_q(), model);
  calibration.check = {last.nees, last.error, steps->check(last.error), steps->current()};
  if (!calibration.check.stable) model.set_process_noise(steps->current(), calibration.period);
  return calibration;
}

IntervalCalibrations calibrate_process_noise_intervals(MotionModel& model, const RegistrationPrior& registration,
                                                       std::span<const Measurement> measurements,
                                                       std::span<const Vector3d> targets,
                                                       std::span<const Matrix3d> target_covariances, double longest,
                                                       bool any_heading) {
  check_targets("calibrate_process_noise_intervals", measurements, targets, target_covariances);
  const double period = model.process_noise_period();
  const double coasting_from = kCoastingStartFactor * model.normalisation().longest_interval;
  IntervalCalibrations result;
  std::vector<IntervalCalibration>& calibrations = result.nodes;
  std::vector<IntervalNoise> forecast_nodes, coasting_nodes;
  model.set_process_noise_intervals({}, {});
  // Strides about 1.4 times apart: each interval within twice the last calibrated one, where a track
  // still coasts (coasting_horizon), so that every stride has predictions to calibrate on.
  bool forecasts_lost = false;  // constant velocity predicted better than Φ at a shorter interval
  for (int stride = 2; calibrations.empty() || calibrations.back().interval < longest * (1.0 - 1e-9);
       stride = std::max(stride + 1, static_cast<int>(std::lround(stride * 1.4)))) {
    const double tau = stride * period;
    const Thinned split = thinned(measurements, targets, target_covariances, period, stride);
    const auto measure = [&](bool coasting) {
      return interval_moment(
          filter_residuals(model, registration, split.measurements, split.targets, split.target_covariances), tau,
          model, coasting, any_heading);
    };
    IntervalCalibration calibration{tau, stride, forecasts_lost || tau > coasting_from, 0, 0.0, 0.0, 0.0,
                                    Matrix3d::Zero()};
    // Round 0 of Φ's curve; then constant velocity at τ under the same Q (a coasting curve that starts
    // at τ makes every track of the thinned split coast): Φ's curve ends where it predicts worse.
    std::optional<IntervalMoment> first;
    if (!calibration.coasting) first = measure(false);
    if (first) {
      model.set_process_noise_intervals(forecast_nodes, {{tau, model.process_noise(tau)}});
      const std::optional<IntervalMoment> rival = measure(true);
      model.set_process_noise_intervals(forecast_nodes, coasting_nodes);
      if (rival) {
        const bool constant_velocity_wins = rival->error < first->error;
        calibration.rival_error = constant_velocity_wins ? first->error : rival->error;
        if (constant_velocity_wins) {
          calibration.coasting = forecasts_lost = true;
          first = rival;
        }
      }
    }
    const bool coasting = calibration.coasting;
    std::vector<IntervalNoise>& nodes = coasting ? coasting_nodes : forecast_nodes;
    // Q never shrinks with the interval along one curve; the coasting curve starts afresh.
    std::optional<Matrix3d> previous;
    if (!coasting) previous = model.process_noise(forecast_nodes.empty() ? period : forecast_nodes.back().interval);
    if (coasting && !coasting_nodes.empty()) previous = coasting_nodes.back().covariance;
    const auto set_model = [&](const std::optional<Matrix3d>& node) {
      std::vector<IntervalNoise> with = nodes;
      if (node) with.push_back({tau, *node});
      model.set_process_noise_intervals(coasting ? forecast_nodes : with, coasting ? with : coasting_nodes);
    };
    // The first coasting round needs a coasting curve for tracks to coast: Φ's Q at τ, for a start.
    if (coasting && coasting_nodes.empty()) set_model(model.process_noise(tau));
    std::optional<Matrix3d> node;
    for (int round = 0; round < 2; ++round) {
      const std::optional<IntervalMoment> measured = round == 0 && first ? first : measure(coasting);
      if (!measured) break;
      // The run with the first round's node ran away: no node at τ, and none beyond.
      if (round == 1 && ran_away(measured->error, calibration.prior_error)) {
        result.diverged_at = tau;
        node.reset();
        break;
      }
      if (round == 0) {
        calibration.predictions = measured->count;
        calibration.prior_nees = measured->nees;
        calibration.prior_error = measured->error;
      }
      node = round == 0 ? measured->moment : Matrix3d(0.5 * (*node + measured->moment));
      if (previous) node = at_least(*node, *previous);
      set_model(node);
    }
    if (!node) {
      model.set_process_noise_intervals(forecast_nodes, coasting_nodes);
      break;
    }
    nodes.push_back({tau, *node});
    calibration.process_noise = *node;
    calibrations.push_back(calibration);
  }
  model.set_process_noise_intervals(forecast_nodes, coasting_nodes);
  return result;
}

}  // namespace stgf
