// SPDX-License-Identifier: Apache-2.0
// The line-of-sight noise and miss model shared by the synthetic, cad and ethucy benchmarks
// (datasets/line_of_sight.hpp): hand-computed bases, R = U diag(σ²) Uᵀ exactly symmetric with
// S Sᵀ = R, and the detection probability.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <vector>

#include "stgf/datasets/line_of_sight.hpp"

namespace stgf {
namespace {

// U is a rotation: UᵀU = I and det U = +1.
void expect_rotation(const Matrix3d& basis) {
  EXPECT_LT((basis.transpose() * basis - Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_NEAR(basis.determinant(), 1.0, 1e-15);
}

// Sensor at the origin, target (3, 4, 0): r = 5, u_r = (0.6, 0.8, 0), u_c = (−0.8, 0.6, 0) and
// u_v = u_r × u_c = (0, 0, 1).
TEST(LineOfSight, HandComputedHorizontalBasis) {
  const LineOfSightNoise sight = line_of_sight(Vector3d::Zero(), Vector3d(3.0, 4.0, 0.0));
  EXPECT_DOUBLE_EQ(sight.range, 5.0);
  Matrix3d expected;
  expected << 0.6, -0.8, 0.0,  //
      0.8, 0.6, 0.0,           //
      0.0, 0.0, 1.0;
  EXPECT_LT((sight.basis - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(sight.standard_deviations, Vector3d::Zero());
  expect_rotation(sight.basis);
}

// Looking straight down: u_r = (0, 0, −1), u_c falls back to (1, 0, 0), u_v = (0, −1, 0); a target
// at the sensor itself gets the same basis with r = 0.
TEST(LineOfSight, VerticalAndZeroRangeFallBackToAFixedBasis) {
  Matrix3d expected;
  expected << 0.0, 1.0, 0.0,  //
      0.0, 0.0, -1.0,         //
      -1.0, 0.0, 0.0;
  const LineOfSightNoise down = line_of_sight(Vector3d(1.0, 2.0, 10.0), Vector3d(1.0, 2.0, 0.0));
  EXPECT_DOUBLE_EQ(down.range, 10.0);
  EXPECT_EQ(down.basis, expected);
  expect_rotation(down.basis);

  const LineOfSightNoise here = line_of_sight(Vector3d(1.0, 2.0, 3.0), Vector3d(1.0, 2.0, 3.0));
  EXPECT_EQ(here.range, 0.0);
  EXPECT_EQ(here.basis, expected);
}

// From a raised sensor: R is exactly symmetric, S Sᵀ = R, R's eigenvalues are the σ² and R u_k =
// σ_k² u_k.
TEST(LineOfSight, CovarianceAndSquareRoot) {
  const std::vector<Vector3d> targets = {Vector3d(-12.5, 7.0, 0.0), Vector3d(30.0, -2.0, 1.5),
                                         Vector3d(0.1, 0.2, 0.0)};
  for (const Vector3d& target : targets) {
    LineOfSightNoise noise = line_of_sight(Vector3d(-25.0, 10.0, 6.0), target);
    noise.standard_deviations = Vector3d(0.5, 0.2, 0.1);
    expect_rotation(noise.basis);
    EXPECT_NEAR(noise.basis.col(0).dot(target - Vector3d(-25.0, 10.0, 6.0)), noise.range, 1e-12);
    EXPECT_EQ(noise.basis(2, 1), 0.0) << "u_c is horizontal";

    const Matrix3d covariance = noise.covariance();
    EXPECT_EQ(covariance, covariance.transpose()) << "symmetric bit for bit";
    const Matrix3d root = noise.square_root();
    EXPECT_LT((root * root.transpose() - covariance).cwiseAbs().maxCoeff(), 1e-15);
    for (int axis = 0; axis < 3; ++axis) {
      const double variance = noise.standard_deviations(axis) * noise.standard_deviations(axis);
      EXPECT_LT((covariance * noise.basis.col(axis) - variance * noise.basis.col(axis)).norm(), 1e-15);
    }
    const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(covariance);
    EXPECT_NEAR(eigen.eigenvalues()(0), 0.01, 1e-15);
    EXPECT_NEAR(eigen.eigenvalues()(1), 0.04, 1e-15);
    EXPECT_NEAR(eigen.eigenvalues()(2), 0.25, 1e-15);
  }
}

// P_near = 0.9, P_far = 0.5, max_range 100 m: 0.9 − 0.4·(50/100)² = 0.8 at 50 m.
TEST(LineOfSight, DetectionProbabilityFallsWithRangeSquared) {
  EXPECT_DOUBLE_EQ(range_detection_probability(0.0, 100.0, 0.9, 0.5), 0.9);
  EXPECT_DOUBLE_EQ(range_detection_probability(50.0, 100.0, 0.9, 0.5), 0.8);
  EXPECT_DOUBLE_EQ(range_detection_probability(100.0, 100.0, 0.9, 0.5), 0.5);
  EXPECT_EQ(range_detection_probability(100.001, 100.0, 0.9, 0.5), 0.0);
  EXPECT_EQ(range_detection_probability(std::nan(""), 100.0, 0.9, 0.5), 0.0);
}

}  // namespace
}  // namespace stgf
