// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/cross_view_weights.hpp"

#include <cmath>

#include <Eigen/Cholesky>

#include "stgf/core/measurement_gate.hpp"

namespace stgf {
namespace {

Matrix3d covariance_of(const CrossViewWeights::Measurement& measurement, double scale) {
  return scale * measurement.noise + measurement.offset;
}

// N(m₋ₖ, M₋ₖ): the information-weighted mean of all but `left_out`, each with its scale.
struct Mean {
  Vector3d mean;
  Matrix3d covariance;
};
Mean others_mean(std::span<const CrossViewWeights::Measurement> measurements, std::span<const double> scales,
                 std::size_t left_out) {
  Matrix3d information = Matrix3d::Zero();
  Vector3d vector = Vector3d::Zero();
  for (std::size_t j = 0; j < measurements.size(); ++j) {
    if (j == left_out) continue;
    const Matrix3d own = covariance_of(measurements[j], scales[j]).llt().solve(Matrix3d::Identity());
    information += own;
    vector += own * measurements[j].corrected;
  }
  const Eigen::LLT<Matrix3d> factor(information);
  return {factor.solve(vector), factor.solve(Matrix3d::Identity())};
}

// d²_k(s) = ν_kᵀ (s N_k + O_k + M₋ₖ)⁻¹ ν_k.
double distance_squared_at(const CrossViewWeights::Measurement& measurement, const Mean& others, double scale) {
  return distance_squared(measurement.corrected - others.mean, covariance_of(measurement, scale) + others.covariance);
}

// The smallest s ≥ 1 with d²(s) ≤ γ (d² falls as s grows), by bisection on log₂ s.
double scale_to_threshold(const CrossViewWeights::Measurement& measurement, const Mean& others, double threshold) {
  double low = 0.0, high = 1.0;
  while (distance_squared_at(measurement, others, std::exp2(high)) > threshold && high < 100.0) high *= 2.0;
  for (int i = 0; i < 40; ++i) {
    const double middle = 0.5 * (low + high);
    (distance_squared_at(measurement, others, std::exp2(middle)) > threshold ? low : high) = middle;
  }
  return std::exp2(high);
}

}  // namespace

double CrossViewWeights::threshold() {
  static const double gamma = chi_square_3_quantile(kProbability);
  return gamma;
}

std::vector<double> CrossViewWeights::noise_scales(std::span<const Measurement> measurements) {
  const std::size_t n = measurements.size();
  std::vector<double> scales(n, 1.0);
  if (n < 3) return scales;
  const double gamma = threshold();
  std::vector<bool> scaled(n, false);
  for (std::size_t round = 0; round + 2 < n; ++round) {
    // The measurement, not yet scaled, that disagrees most with the others' mean.
    std::size_t worst = n;
    double worst_distance = gamma;
    Mean worst_others{};
    for (std::size_t k = 0; k < n; ++k) {
      if (scaled[k]) continue;
      const Mean others = others_mean(measurements, scales, k);
      const double distance = distance_squared_at(measurements[k], others, 1.0);
      if (distance > worst_distance) {
        worst = k;
        worst_distance = distance;
        worst_others = others;
      }
    }
    if (worst == n) break;
    scales[worst] = scale_to_threshold(measurements[worst], worst_others, gamma);
    scaled[worst] = true;
  }
  return scales;
}

}  // namespace stgf
