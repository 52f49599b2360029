// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/registration_calibration.hpp"

#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "stgf/core/steps.hpp"

namespace stgf {
namespace {

// log10 of σ_x, σ_y, σ_z, α_along, α_across, α_vertical, σ_ε
using Parameters = std::array<double, kOffsetSize>;
constexpr int kRangeScale = kOffsetSize - 1;  // ε's coordinate

// A group's evidence on the offsets β of its views (kOffsetSize coordinates per view, or one fewer
// once ε is left out): information A, vector b.
struct GroupStatistics {
  Eigen::MatrixXd a;
  Eigen::VectorXd b;
  int size = kOffsetSize;  // coordinates per view
  explicit GroupStatistics(Eigen::Index views = 1)
      : a(Eigen::MatrixXd::Zero(kOffsetSize * views, kOffsetSize * views)),
        b(Eigen::VectorXd::Zero(kOffsetSize * views)) {}
};

// Without the range scale: each group's A and b on every view's coordinates but ε, so that the
// likelihood is exactly that of the model without it.
void leave_out_range_scale(std::vector<GroupStatistics>& groups) {
  for (GroupStatistics& group : groups) {
    const Eigen::Index views = group.b.size() / kOffsetSize;
    std::vector<Eigen::Index> kept;
    for (Eigen::Index view = 0; view < views; ++view) {
      for (int k = 0; k < kRangeScale; ++k) kept.push_back(kOffsetSize * view + k);
    }
    group.a = Eigen::MatrixXd(group.a(kept, kept));
    group.b = Eigen::VectorXd(group.b(kept));
    group.size = kRangeScale;
  }
}

constexpr double kLowest = -4.0;                            // log10 of the smallest σ or α
constexpr Parameters kHighest = {1.5, 1.5, 1.5, 2.0, 2.0, 2.0, 0.0};  // σ_ε up to 1 (100 %)

// GCC 12 cannot see that group.size ≤ kOffsetSize below and warns that Eigen's packet loads of
// information.head(group.size) may read past the vector (-Warray-bounds, a false positive).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Warray-bounds"
#endif
double log_likelihood(const std::vector<GroupStatistics>& groups, const Parameters& parameters) {
  Eigen::Matrix<double, kOffsetSize, 1> information;
  for (int k = 0; k < kOffsetSize; ++k) information[k] = std::pow(10.0, -2.0 * parameters[k]);
  double total = 0.0;
  for (const GroupStatistics& group : groups) {
    const auto prior_information = information.head(group.size);
    const double log_det_prior = prior_information.array().log().sum();
    const Eigen::Index views = group.b.size() / group.size;
    Eigen::MatrixXd posterior_information = group.a;
    posterior_information.diagonal() += prior_information.replicate(views, 1);
    const Eigen::LLT<Eigen::MatrixXd> factor(posterior_information);
    const double log_det = 2.0 * factor.matrixLLT().diagonal().array().log().sum();
    total -=
        0.5 * (-group.b.dot(factor.solve(group.b)) + log_det - static_cast<double>(views) * log_det_prior);
  }
  return total;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// The coordinates a search coordinate sets: itself, or with one α for all three axes, α's three.
int last_of(int coordinate, NoiseRatioAxes axes) {
  return axes == NoiseRatioAxes::kOne && coordinate == 3 ? 5 : coordinate;
}

// Whether the search moves this coordinate on its own: not α's second and third with one α (they
// follow the first), nor ε when it is left out (it stays at zero).
bool searched(int coordinate, NoiseRatioAxes axes, bool range_scale) {
  if (axes == NoiseRatioAxes::kOne && (coordinate == 4 || coordinate == 5)) return false;
  return coordinate != kRangeScale || range_scale;
}

// Best value of one search coordinate on the grid lo, lo + step, …, hi (others fixed).
double best_on_grid(const std::vector<GroupStatistics>& groups, Parameters parameters, int coordinate, double lo,
                    double hi, double step, NoiseRatioAxes axes) {
  double best_value = parameters[coordinate];
  double best = log_likelihood(groups, parameters);
  for (double value = lo; value <= hi + 1e-9; value += step) {
    for (int k = coordinate; k <= last_of(coordinate, axes); ++k) parameters[k] = value;
    const double candidate = log_likelihood(groups, parameters);
    if (candidate > best) {
      best = candidate;
      best_value = value;
    }
  }
  return best_value;
}

// The parameters that maximise the groups' marginal likelihood.
RegistrationCalibration maximise_likelihood(std::vector<GroupStatistics> groups, NoiseRatioAxes axes, bool range_scale) {
  if (!range_scale) leave_out_range_scale(groups);
  RegistrationCalibration result;
  result.groups = groups.size();
  if (groups.empty()) return result;
  Parameters parameters;
  parameters.fill(kLowest);
  const double none = log_likelihood(groups, parameters);
  for (const double step : {0.1, 0.01}) {
    for (int sweep = 0; sweep < 20; ++sweep) {
      const Parameters before = parameters;
      for (int coordinate = 0; coordinate < kOffsetSize; ++coordinate) {
        if (!searched(coordinate, axes, range_scale)) continue;
        const double lo = step < 0.1 ? std::max(kLowest, parameters[coordinate] - 0.1) : kLowest;
        const double hi = step < 0.1 ? std::min(kHighest[coordinate], parameters[coordinate] + 0.1) : kHighest[coordinate];
        const double best = best_on_grid(groups, parameters, coordinate, lo, hi, step, axes);
        for (int k = coordinate; k <= last_of(coordinate, axes); ++k) parameters[k] = best;
      }
      if (parameters == before) break;
    }
  }
  auto sigma = [](double log10_value) { return log10_value <= kLowest + 1e-9 ? 0.0 : std::pow(10.0, log10_value); };
  result.prior.translation_sigma = Vector3d(sigma(parameters[0]), sigma(parameters[1]), sigma(parameters[2]));
  result.prior.noise_ratio = Vector3d(sigma(parameters[3]), sigma(parameters[4]), sigma(parameters[5]));
  result.prior.range_scale_sigma = sigma(parameters[kRangeScale]);
  result.log_likelihood_gain = (log_likelihood(groups, parameters) - none) / static_cast<double>(groups.size());
  return result;
}

}  // namespace

RegistrationCalibration calibrate_registration_prior(std::span<const Measurement> measurements,
                                                     std::span<const Vector3d> truth, NoiseRatioAxes axes,
                                                     bool range_scale) {
  if (measurements.size() != truth.size()) {
    throw std::invalid_argument("calibrate_registration_prior: one truth position per measurement");
  }
  std::map<std::pair<std::string, std::string>, GroupStatistics> by_group;
  for (std::size_t k = 0; k < measurements.size(); ++k) {
    const Measurement& measurement = measurements[k];
    // ε's column from the measurement, not the truth: against the truth each view's offsets are fitted
    // alone, and the measurement's noise in its column costs only ε times that noise, second order.
    // (From the truth, mpl's α per axis with the range scale came out at a far corner of a nearly flat
    // ridge — α along the rays 7.2, σ_ε 0.093 — and its model lost 9 % of DE on mpl test.) Differences
    // between views are another matter (below; offset_jacobian).
    const Eigen::Matrix<double, 3, kOffsetSize> jacobian = offset_jacobian(measurement);
    const Eigen::Matrix<double, kOffsetSize, 3> weighted =
        jacobian.transpose() * measurement.position.information();
    GroupStatistics& group = by_group.try_emplace({measurement.scene, measurement.view}).first->second;
    group.a.noalias() += weighted * jacobian;
    group.b.noalias() += weighted * (measurement.position.mean() - truth[k]);
  }
  std::vector<GroupStatistics> groups;
  groups.reserve(by_group.size());
  for (auto& entry : by_group) groups.push_back(std::move(entry.second));
  return maximise_likelihood(std::move(groups), axes, range_scale);
}

RegistrationCalibration calibrate_registration_prior_from_disagreements(
    std::span<const Measurement> measurements, NoiseRatioAxes axes, bool range_scale) {
  std::vector<GroupStatistics> groups;
  for (const Scene& scene : group_into_scenes(measurements)) {
    // The scene's views, in order of first appearance: view u's offset is β[7u, 7u + 7).
    std::map<std::string, Eigen::Index> view_index;
    for (const Step& step : scene.steps) {
      for (const std::size_t row : step.rows) {
        view_index.try_emplace(measurements[row].view, static_cast<Eigen::Index>(view_index.size()));
      }
    }
    GroupStatistics group(static_cast<Eigen::Index>(view_index.size()));
    bool disagreed = false;
    for (const Step& step : scene.steps) {
      // The step's rows by object (list order within each object).
      std::map<std::string_view, std::vector<std::size_t>> rows_of_object;
      for (const std::size_t row : step.rows) rows_of_object[measurements[row].object].push_back(row);
      for (const auto& [object, rows] : rows_of_object) {
        if (rows.size() < 2) continue;
        disagreed = true;
        // With p marginalised under a flat prior (registration_prior_scale.hpp):
        //   A_j = Σ_k H_kᵀ W_k H_k − Fᵀ S⁻¹ F,   b_j = Σ_k H_kᵀ W_k z_k − Fᵀ S⁻¹ y,
        //   S = Σ_k W_k,  F = Σ_k W_k G_k (G_k = H_k in view u_k's columns),  y = Σ_k W_k z_k.
        const std::size_t k = rows.size();
        std::vector<Eigen::Matrix<double, 3, kOffsetSize>> weighted_jacobian(k);  // W_k H_k
        std::vector<Eigen::Index> column(k);
        Matrix3d information_sum = Matrix3d::Zero();
        Vector3d weighted_sum = Vector3d::Zero();
        for (const std::size_t row : rows) {
          information_sum += measurements[row].position.information();
          weighted_sum += measurements[row].position.information() * measurements[row].position.mean();
        }
        const Eigen::LLT<Matrix3d> total(information_sum);
        const Vector3d mean = total.solve(weighted_sum);  // S⁻¹ y: ε's column is taken from it (offset_jacobian)
        for (std::size_t j = 0; j < k; ++j) {
          const Measurement& measurement = measurements[rows[j]];
          const Matrix3d& information = measurement.position.information();
          const Eigen::Matrix<double, 3, kOffsetSize> jacobian = offset_jacobian(measurement, mean);
          weighted_jacobian[j] = information * jacobian;
          column[j] = kOffsetSize * view_index.at(measurement.view);
          group.a.block<kOffsetSize, kOffsetSize>(column[j], column[j]).noalias() +=
              jacobian.transpose() * weighted_jacobian[j];
          group.b.segment<kOffsetSize>(column[j]).noalias() +=
              weighted_jacobian[j].transpose() * measurement.position.mean();
        }
        for (std::size_t i = 0; i < k; ++i) {
          const Eigen::Matrix<double, 3, kOffsetSize> spread =
              total.solve(weighted_jacobian[i]);  // S⁻¹ W_i H_i
          group.b.segment<kOffsetSize>(column[i]).noalias() -= weighted_jacobian[i].transpose() * mean;
          for (std::size_t j = 0; j < k; ++j) {
            group.a.block<kOffsetSize, kOffsetSize>(column[j], column[i]).noalias() -=
                weighted_jacobian[j].transpose() * spread;
          }
        }
      }
    }
    if (disagreed) groups.push_back(std::move(group));
  }
  return maximise_likelihood(std::move(groups), axes, range_scale);
}

}  // namespace stgf
