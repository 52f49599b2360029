// SPDX-License-Identifier: Apache-2.0
// Q(τ) of a motion model with nodes at longer intervals (core/process_noise_curve.hpp).

#include "stgf/core/process_noise_curve.hpp"

#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

namespace stgf {
namespace {

double largest_difference(const Matrix3d& a, const Matrix3d& b) { return (a - b).cwiseAbs().maxCoeff(); }

TEST(ProcessNoiseCurve, WithoutNodesQGrowsLinearlyUpToTheReferenceIntervalAndAsItsSquareBeyond) {
  const Matrix3d reference = Vector3d(0.01, 0.02, 0.001).asDiagonal();
  EXPECT_LT(largest_difference(process_noise_at(reference, 0.1, {}, 0.3), 9.0 * reference), 1e-15);
  EXPECT_LT(largest_difference(process_noise_at(reference, 0.1, {}, 0.1), reference), 1e-15);
  EXPECT_LT(largest_difference(process_noise_at(reference, 0.1, {}, 0.05), 0.5 * reference), 1e-15);
  // Below the reference interval the increments add up: Q(τ) − Q(τ_s) = Q(τ − τ_s).
  EXPECT_LT(largest_difference(process_noise_at(reference, 0.1, {}, 0.08) - process_noise_at(reference, 0.1, {}, 0.03),
                               process_noise_at(reference, 0.1, {}, 0.05)),
            1e-15);
}

TEST(ProcessNoiseCurve, TheShrinkageInvertsTheGrowthOnBothSidesOfTheReferenceInterval) {
  for (const double tau : {0.01, 0.05, 0.1, 0.2, 0.7}) {
    EXPECT_NEAR(reference_growth(0.1, tau) * reference_shrinkage(0.1, tau), 1.0, 1e-14) << tau;
  }
  EXPECT_EQ(reference_shrinkage(0.1, 0.05), 2.0);
  EXPECT_EQ(reference_shrinkage(0.1, 0.2), 0.25);
}

TEST(ProcessNoiseCurve, PassesThroughItsNodesGrowingBetweenAndBeyondThem) {
  const Matrix3d reference = 0.01 * Matrix3d::Identity();
  const std::vector<IntervalNoise> nodes = {{0.2, Vector3d(0.05, 0.06, 0.02).asDiagonal()},
                                            {0.4, Vector3d(0.3, 0.2, 0.02).asDiagonal()}};
  // Below the reference interval: linear in τ.
  EXPECT_LT(largest_difference(process_noise_at(reference, 0.1, nodes, 0.05), 0.5 * reference), 1e-15);
  // At and between the nodes: through them, linear in τ².
  EXPECT_LT(largest_difference(process_noise_at(reference, 0.1, nodes, 0.2), nodes[0].covariance), 1e-15);
  EXPECT_LT(largest_difference(process_noise_at(reference, 0.1, nodes, 0.4), nodes[1].covariance), 1e-15);
  const double share = (0.3 * 0.3 - 0.2 * 0.2) / (0.4 * 0.4 - 0.2 * 0.2);
  EXPECT_LT(largest_difference(process_noise_at(reference, 0.1, nodes, 0.3),
                               nodes[0].covariance + share * (nodes[1].covariance - nodes[0].covariance)),
            1e-15);
  // Beyond the last: as τ³.
  EXPECT_LT(largest_difference(process_noise_at(reference, 0.1, nodes, 0.8), 8.0 * nodes[1].covariance), 1e-14);
  // Every increment is a covariance.
  double previous_tau = 0.0;
  Matrix3d previous = Matrix3d::Zero();
  for (double tau = 0.01; tau < 1.5; tau += 0.01) {
    const Matrix3d q = process_noise_at(reference, 0.1, nodes, tau);
    const Eigen::SelfAdjointEigenSolver<Matrix3d> growth(q - previous);
    EXPECT_GE(growth.eigenvalues().minCoeff(), -1e-15) << previous_tau << " to " << tau;
    previous = q;
    previous_tau = tau;
  }
}

TEST(ProcessNoiseCurve, TheCoastingCurveStartsFromItsFirstNode) {
  const std::vector<IntervalNoise> nodes = {{0.5, 0.04 * Matrix3d::Identity()}, {1.0, 0.2 * Matrix3d::Identity()}};
  EXPECT_LT(largest_difference(coasting_process_noise_at(nodes, 0.25), 0.02 * Matrix3d::Identity()), 1e-15);
  EXPECT_LT(largest_difference(coasting_process_noise_at(nodes, 1.0), nodes[1].covariance), 1e-15);
  EXPECT_LT(largest_difference(coasting_process_noise_at(nodes, 2.0), 1.6 * Matrix3d::Identity()), 1e-14);
}

}  // namespace
}  // namespace stgf
