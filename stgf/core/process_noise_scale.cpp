#include "stgf/core/process_noise_scale.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

namespace stgf {
namespace {

constexpr double kLowestLog2 = 0.0;
constexpr double kLog2Step = 0.5;

double grid_scale(int point) { return std::exp2(kLowestLog2 + kLog2Step * point); }

}  // namespace

ProcessNoiseScale::ProcessNoiseScale() {
  for (int point = 0; point < kGridPoints; ++point) {
    const double log_scale = std::log(grid_scale(point));
    log_posterior_[point] = -0.5 * log_scale * log_scale;
  }
}

void ProcessNoiseScale::add(const Vector3d& innovation, const Matrix3d& known_covariance,
                            const Matrix3d& process_noise, double weight) {
  if (!(weight > 0.0) || !innovation.allFinite()) throw std::invalid_argument("ProcessNoiseScale::add: bad innovation or weight");
  int best = 0;
  for (int point = 0; point < kGridPoints; ++point) {
    const Matrix3d covariance = known_covariance + grid_scale(point) * process_noise;
    const Eigen::LDLT<Matrix3d> factor(covariance);
    const double log_det = factor.vectorD().array().log().sum();
    log_posterior_[point] -= 0.5 * weight * (innovation.dot(factor.solve(innovation)) + log_det);
    if (log_posterior_[point] > log_posterior_[best]) best = point;
  }
  scale_ = grid_scale(best);
  ++innovations_;
}

}  // namespace stgf
