// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/process_noise_scale.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

namespace stgf {
namespace {

constexpr double kLowestLog2 = -10.0;
constexpr double kLog2Step = 0.5;
constexpr double kPriorSigma = 3.0;  // of ln λ
static_assert(kLowestLog2 + kLog2Step * ProcessNoiseScale::kUnitPoint == 0.0);

// λ at each grid point, computed once (add() reads all of them for every innovation).
const std::array<double, ProcessNoiseScale::kGridPoints>& grid_scales() {
  static const std::array<double, ProcessNoiseScale::kGridPoints> scales = [] {
    std::array<double, ProcessNoiseScale::kGridPoints> result{};
    for (int point = 0; point < ProcessNoiseScale::kGridPoints; ++point) {
      result[point] = std::exp2(kLowestLog2 + kLog2Step * point);
    }
    return result;
  }();
  return scales;
}

double grid_scale(int point) { return grid_scales()[point]; }

}  // namespace

ProcessNoiseScale ProcessNoiseScale::learning_the_whole_grid() {
  ProcessNoiseScale scale;
  scale.first_point_ = 0;
  return scale;
}

ProcessNoiseScale::ProcessNoiseScale() {
  for (auto& axis : log_posterior_) {
    for (int point = 0; point < kGridPoints; ++point) {
      const double log_scale = std::log(grid_scale(point));
      axis[point] = -0.5 * log_scale * log_scale / (kPriorSigma * kPriorSigma);
    }
  }
}

ProcessNoiseScale::ProcessNoiseScale(const Grid& evidence, bool below_one) : ProcessNoiseScale() {
  for (int a = 0; a < 3; ++a) {
    for (int point = 0; point < kGridPoints; ++point) {
      if (!std::isfinite(evidence[a][point])) throw std::invalid_argument("ProcessNoiseScale: evidence must be finite");
      log_posterior_[a][point] += evidence[a][point];
    }
  }
  first_point_ = 0;
  lowest_point_ = below_one ? 0 : kUnitPoint;
  choose_scales();
}

void ProcessNoiseScale::choose_scales() {
  for (int a = 0; a < 3; ++a) {
    int best = lowest_point_;
    for (int point = lowest_point_ + 1; point < kGridPoints; ++point) {
      if (log_posterior_[a][point] > log_posterior_[a][best]) best = point;
    }
    scales_[a] = grid_scale(best);
  }
}

ProcessNoiseScale::Grid ProcessNoiseScale::evidence_since(const ProcessNoiseScale& start) const {
  Grid evidence{};
  for (int a = 0; a < 3; ++a) {
    for (int point = 0; point < kGridPoints; ++point) evidence[a][point] = log_posterior_[a][point] - start.log_posterior_[a][point];
  }
  return evidence;
}

void ProcessNoiseScale::add(const Vector3d& innovation, const Matrix3d& known_covariance,
                            const Matrix3d& process_noise, double weight) {
  if (!(weight > 0.0) || !innovation.allFinite()) {
    throw std::invalid_argument("ProcessNoiseScale::add: bad innovation or weight");
  }
  for (int a = 0; a < 3; ++a) {
    auto& axis = log_posterior_[a];
    const double squared = innovation[a] * innovation[a];
    int best = lowest_point_;
    const std::array<double, kGridPoints>& scales = grid_scales();
    for (int point = first_point_; point < kGridPoints; ++point) {
      const double variance = known_covariance(a, a) + scales[point] * process_noise(a, a);
      if (variance > 0.0) axis[point] -= 0.5 * weight * (squared / variance + std::log(variance));
      if (point >= lowest_point_ && axis[point] > axis[best]) best = point;
    }
    scales_[a] = grid_scale(best);
  }
  ++innovations_;
}

Matrix3d ProcessNoiseScale::scaled(const Matrix3d& process_noise) const {
  const Vector3d root = scales_.cwiseSqrt();
  return root.asDiagonal() * process_noise * root.asDiagonal();
}

}  // namespace stgf
