// SPDX-License-Identifier: Apache-2.0
// One object's measurements within a frame, moved along the track's path to one time
// (core/frame_alignment.hpp): each by the displacement predicted up to its time, with |C_k − C_mid|
// for the path's error.

#include "stgf/core/frame_alignment.hpp"

#include <string>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

namespace stgf {
namespace {

Measurement at(double time, const std::string& view, const Vector3d& z) {
  return Measurement{"s", time, view, "o", Gaussian3::from_covariance(z, 0.04 * Matrix3d::Identity()), std::nullopt, std::nullopt};
}

TEST(FrameAlignment, MovesEachMeasurementBackAlongThePathAndAddsItsErrorFromTheMiddle) {
  FrameAlignment frame;
  frame.gather(at(0.00, "a", Vector3d(1.0, 2.0, 0.0)), 1.0);
  const Matrix3d step = Vector3d(1e-3, 2e-3, 1e-4).asDiagonal();
  frame.follow(Vector3d(0.05, -0.02, 0.0), step);
  frame.gather(at(0.05, "b", Vector3d(1.06, 1.97, 0.0)), 2.0);
  frame.follow(Vector3d(0.05, -0.02, 0.0), step);
  frame.gather(at(0.10, "c", Vector3d(1.09, 1.96, 0.1)), 1.0);
  ASSERT_EQ(frame.size(), 3u);

  const FrameAlignment::Aligned aligned = frame.aligned();
  ASSERT_EQ(aligned.measurements.size(), 3u);
  EXPECT_LE((aligned.measurements[0].position.mean() - Vector3d(1.0, 2.0, 0.0)).norm(), 1e-15);
  EXPECT_LE((aligned.measurements[1].position.mean() - Vector3d(1.01, 1.99, 0.0)).norm(), 1e-15);
  EXPECT_LE((aligned.measurements[2].position.mean() - Vector3d(0.99, 2.0, 0.1)).norm(), 1e-15);
  // The measurement's own noise, view and time are kept; the noise scale goes with it.
  EXPECT_EQ(aligned.measurements[1].view, "b");
  EXPECT_EQ(aligned.measurements[1].time, 0.05);
  EXPECT_LE((aligned.measurements[1].position.covariance() - 0.04 * Matrix3d::Identity()).norm(), 1e-15);
  EXPECT_EQ(aligned.noise_scales[1], 2.0);
  // C = 0, step, 2 step; the middle is step: the ends get step each, the middle nothing.
  EXPECT_LE((aligned.covariances[0] - step).norm(), 1e-15);
  EXPECT_LE(aligned.covariances[1].norm(), 1e-15);
  EXPECT_LE((aligned.covariances[2] - step).norm(), 1e-15);
}

TEST(FrameAlignment, TheAddedCovarianceIsPositiveSemidefiniteWhenThePathIsNotOrdered) {
  // Q's scale changed within the frame: C_2 − C_mid is neither ⪰ 0 nor ⪯ 0.
  FrameAlignment frame;
  frame.gather(at(0.0, "a", Vector3d::Zero()), 1.0);
  frame.follow(Vector3d::Zero(), Vector3d(4e-3, 1e-4, 1e-4).asDiagonal());
  frame.gather(at(0.05, "b", Vector3d::Zero()), 1.0);
  frame.follow(Vector3d::Zero(), Vector3d(1e-4, 4e-3, 1e-4).asDiagonal());
  frame.gather(at(0.1, "c", Vector3d::Zero()), 1.0);
  for (const Matrix3d& covariance : frame.aligned().covariances) {
    const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(covariance);
    EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-15);
    EXPECT_LE((covariance - covariance.transpose()).norm(), 1e-18);
  }
  // The middle measurement: |C_2 − (C_1 + C_3)/2| = |diag(1.95e-3, −1.95e-3, 0)| = diag(1.95e-3, 1.95e-3, 0).
  const Matrix3d middle = frame.aligned().covariances[1];
  EXPECT_LE((middle - Vector3d(1.95e-3, 1.95e-3, 0.0).asDiagonal().toDenseMatrix()).norm(), 1e-15);
}

TEST(FrameAlignment, NothingGatheredGivesNothing) {
  FrameAlignment frame;
  frame.follow(Vector3d(1, 2, 3), Matrix3d::Identity());
  EXPECT_EQ(frame.size(), 0u);
  EXPECT_TRUE(frame.aligned().measurements.empty());
}

}  // namespace
}  // namespace stgf
