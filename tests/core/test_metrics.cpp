// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/metrics.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "support/random_spd.hpp"

namespace stgf {
namespace {

// CDF of χ²(3): erf(√(x/2)) − √(2x/π) e^(−x/2).
double chi_square3_cdf(double x) {
  return std::erf(std::sqrt(x / 2.0)) - std::sqrt(2.0 * x / std::numbers::pi) * std::exp(-x / 2.0);
}

TEST(Metrics, IntervalBoundsAreTheChiSquareQuantiles) {
  EXPECT_NEAR(chi_square3_cdf(kChiSquare3Lower95), 0.025, 1e-12);
  EXPECT_NEAR(chi_square3_cdf(kChiSquare3Upper95), 0.975, 1e-12);
}

TEST(Metrics, HandComputedRows) {
  ErrorAccumulator accumulator;
  const Gaussian3 a = Gaussian3::from_covariance(Vector3d(3, 4, 0), Matrix3d::Identity());
  const Gaussian3 b = Gaussian3::from_covariance(Vector3d(0, 0, 1), 4.0 * Matrix3d::Identity());
  accumulator.add(a, Vector3d::Zero(), Vector3d(0, 10, 0));  // error 5, range 10, NEES 25
  accumulator.add(b, Vector3d::Zero(), Vector3d(0, 0, -2));  // error 1, range 2, NEES 0.25
  const ErrorSummary summary = accumulator.summary();
  EXPECT_EQ(summary.rows, 2u);
  EXPECT_DOUBLE_EQ(summary.displacement_error, 3.0);
  EXPECT_DOUBLE_EQ(summary.relative_displacement_error, (0.5 + 0.5) / 2);
  EXPECT_DOUBLE_EQ(summary.nees_mean, (25.0 + 0.25) / 2);
  EXPECT_DOUBLE_EQ(summary.nees_share_in_95, 0.5);
  EXPECT_DOUBLE_EQ(summary.nees_horizontal_mean, (25.0 + 0.0) / 2);
  EXPECT_DOUBLE_EQ(summary.nees_vertical_mean, (0.0 + 0.25) / 2);
}

// The horizontal marginal uses P̂'s x-y block, not the inverse's: with x and y correlated by 0.8, an
// error (1, 1) has e_hᵀ P_hh⁻¹ e_h = 2 / (1 + 0.8); z's variance and its correlation with x play no part.
TEST(Metrics, NeesByDirectionUsesTheMarginals) {
  Matrix3d covariance;
  covariance << 1.0, 0.8, 0.5, 0.8, 1.0, 0.0, 0.5, 0.0, 4.0;
  ErrorAccumulator accumulator;
  accumulator.add(Gaussian3::from_covariance(Vector3d(1, 1, 1), covariance), Vector3d::Zero(), std::nullopt);
  const ErrorSummary summary = accumulator.summary();
  EXPECT_NEAR(summary.nees_horizontal_mean, 2.0 / 1.8, 1e-12);
  EXPECT_NEAR(summary.nees_vertical_mean, 0.25, 1e-12);
}

TEST(Metrics, RelativeErrorNeedsEverySensor) {
  ErrorAccumulator accumulator;
  const Gaussian3 a = Gaussian3::from_covariance(Vector3d(1, 0, 0), Matrix3d::Identity());
  accumulator.add(a, Vector3d::Zero(), Vector3d(0, 10, 0));
  accumulator.add(a, Vector3d::Zero(), std::nullopt);
  EXPECT_TRUE(std::isnan(accumulator.summary().relative_displacement_error));
  EXPECT_DOUBLE_EQ(accumulator.summary().displacement_error, 1.0);
}

TEST(Metrics, EmptySetIsUndefined) {
  const ErrorSummary summary = ErrorAccumulator{}.summary();
  EXPECT_EQ(summary.rows, 0u);
  EXPECT_TRUE(std::isnan(summary.displacement_error));
}

// Errors drawn from the stated covariance give NEES ≈ 3 and ≈ 95% inside the interval.
// NEES ~ χ²(3) has variance 6, so over 20000 rows its mean has standard error √(6/20000) ≈ 0.017;
// the share has standard error √(0.95·0.05/20000) ≈ 0.0015. Bounds are 5 standard errors.
TEST(Metrics, CalibratedErrorsGiveNeesThree) {
  std::mt19937_64 rng(21);
  std::normal_distribution<double> normal;
  ErrorAccumulator accumulator;
  const int rows = 20000;
  for (int k = 0; k < rows; ++k) {
    const Matrix3d covariance = testing::random_spd(rng, 0.5, 50.0);
    const Matrix3d l = Eigen::LLT<Matrix3d>(covariance).matrixL();
    const Vector3d error = l * Vector3d(normal(rng), normal(rng), normal(rng));
    accumulator.add(Gaussian3::from_covariance(error, covariance), Vector3d::Zero(), std::nullopt);
  }
  const ErrorSummary summary = accumulator.summary();
  EXPECT_NEAR(summary.nees_mean, 3.0, 5 * std::sqrt(6.0 / rows));
  EXPECT_NEAR(summary.nees_share_in_95, 0.95, 5 * std::sqrt(0.95 * 0.05 / rows));
  // The marginals are χ²(2) and χ²(1): variances 4 and 2.
  EXPECT_NEAR(summary.nees_horizontal_mean, 2.0, 5 * std::sqrt(4.0 / rows));
  EXPECT_NEAR(summary.nees_vertical_mean, 1.0, 5 * std::sqrt(2.0 / rows));
}

}  // namespace
}  // namespace stgf
