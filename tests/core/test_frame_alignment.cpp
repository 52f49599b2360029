// SPDX-License-Identifier: Apache-2.0
// One object's measurements within a frame, moved along the track's path to one time
// (core/frame_alignment.hpp): each by the displacement predicted up to its time, with |C_k − C_mid|
// for the path's error.

#include "stgf/core/frame_alignment.hpp"

#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

namespace stgf {
namespace {

Measurement at(double time, const std::string& view, const Vector3d& z) {
  return Measurement{"s", time, view, "o", Gaussian3::from_covariance(z, 0.04 * Matrix3d::Identity()), std::nullopt, std::nullopt};
}

// FrameAlignment::aligned's three lists.
struct Aligned {
  explicit Aligned(const FrameAlignment& frame) { frame.aligned(measurements, noise_scales, covariances); }
  std::vector<const Measurement*> measurements;
  std::vector<double> noise_scales;
  std::vector<Matrix3d> covariances;
};

TEST(FrameAlignment, MovesEachMeasurementBackAlongThePathAndAddsItsErrorFromTheMiddle) {
  FrameAlignment frame;
  frame.gather(at(0.00, "a", Vector3d(1.0, 2.0, 0.0)), 1.0);
  const Matrix3d step = Vector3d(1e-3, 2e-3, 1e-4).asDiagonal();
  frame.follow(Vector3d(0.05, -0.02, 0.0), step);
  frame.gather(at(0.05, "b", Vector3d(1.06, 1.97, 0.0)), 2.0);
  frame.follow(Vector3d(0.05, -0.02, 0.0), step);
  frame.gather(at(0.10, "c", Vector3d(1.09, 1.96, 0.1)), 1.0);
  ASSERT_EQ(frame.size(), 3u);

  const Aligned aligned(frame);
  ASSERT_EQ(aligned.measurements.size(), 3u);
  EXPECT_LE((aligned.measurements[0]->position.mean() - Vector3d(1.0, 2.0, 0.0)).norm(), 1e-15);
  EXPECT_LE((aligned.measurements[1]->position.mean() - Vector3d(1.01, 1.99, 0.0)).norm(), 1e-15);
  EXPECT_LE((aligned.measurements[2]->position.mean() - Vector3d(0.99, 2.0, 0.1)).norm(), 1e-15);
  // The measurement's own noise, view and time are kept; the noise scale goes with it.
  EXPECT_EQ(aligned.measurements[1]->view, "b");
  EXPECT_EQ(aligned.measurements[1]->time, 0.05);
  EXPECT_LE((aligned.measurements[1]->position.covariance() - 0.04 * Matrix3d::Identity()).norm(), 1e-15);
  EXPECT_EQ(aligned.noise_scales[1], 2.0);
  // C = 0, step, 2 step; the middle is step: the ends get step each, the middle nothing.
  EXPECT_LE((aligned.covariances[0] - step).norm(), 1e-15);
  EXPECT_LE(aligned.covariances[1].norm(), 1e-15);
  EXPECT_LE((aligned.covariances[2] - step).norm(), 1e-15);
}

TEST(FrameAlignment, TheAddedCovarianceIsPositiveSemidefiniteWhenThePathBends) {
  // Q's scale changed within the frame: C_2 − C_mid is neither ⪰ 0 nor ⪯ 0.
  FrameAlignment frame;
  frame.gather(at(0.0, "a", Vector3d::Zero()), 1.0);
  const Matrix3d first = Vector3d(4e-3, 1e-4, 1e-4).asDiagonal(), second = Vector3d(1e-4, 4e-3, 1e-4).asDiagonal();
  frame.follow(Vector3d::Zero(), first);
  frame.gather(at(0.05, "b", Vector3d::Zero()), 1.0);
  frame.follow(Vector3d::Zero(), second);
  frame.gather(at(0.1, "c", Vector3d::Zero()), 1.0);
  const Aligned aligned(frame);
  for (const Matrix3d& covariance : aligned.covariances) {
    const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(covariance);
    EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-18);
  }
  // Halfway along the path by trace: the middle one gets nothing, the ends half the path each.
  EXPECT_LE(aligned.covariances[1].norm(), 1e-18);
  EXPECT_LE((aligned.covariances[0] - 0.5 * (first + second)).norm(), 1e-18);
  EXPECT_LE((aligned.covariances[2] - 0.5 * (first + second)).norm(), 1e-18);
}

TEST(FrameAlignment, AStepThatTakesVarianceAwayIsFollowedByWhatItAddsOnly) {
  // A prediction more certain than its state (the slope's terms: −2e-3 on y) adds to the path what it
  // adds on x and z; with it summed as it is, C_n − C_1 was not a covariance, nor a measurement's noise
  // plus A_k (the general model on mpl's own clocks with 3× the calibration error stopped on it).
  FrameAlignment frame;
  frame.gather(at(0.0, "a", Vector3d::Zero()), 1.0);
  frame.follow(Vector3d::Zero(), Vector3d(1e-3, -2e-3, 1e-4).asDiagonal());
  frame.gather(at(0.1, "b", Vector3d::Zero()), 1.0);
  const Aligned aligned(frame);
  for (const Matrix3d& covariance : aligned.covariances) {
    const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(covariance);
    EXPECT_GE(eigen.eigenvalues().minCoeff(), 0.0);
    EXPECT_LE((covariance - Matrix3d(Vector3d(0.5e-3, 0.0, 0.5e-4).asDiagonal())).norm(), 1e-18);
  }
}

TEST(FrameAlignment, NothingGatheredGivesNothing) {
  FrameAlignment frame;
  frame.follow(Vector3d(1, 2, 3), Matrix3d::Identity());
  EXPECT_EQ(frame.size(), 0u);
  EXPECT_TRUE(Aligned(frame).measurements.empty());
}

}  // namespace
}  // namespace stgf
