// SPDX-License-Identifier: Apache-2.0
// The constant-velocity Kalman filter of `mmt`: predict and update against the textbook matrix
// formulas, many views per step against one view at a time, and rate independence.

#include "stgf/core/constant_velocity_filter.hpp"

#include <random>

#include <Eigen/LU>
#include <gtest/gtest.h>

#include "support/random_spd.hpp"

namespace stgf {
namespace {

using Matrix36d = Eigen::Matrix<double, 3, 6>;

Matrix6d transition(double dt) {
  Matrix6d f = Matrix6d::Identity();
  f.topRightCorner<3, 3>() = dt * Matrix3d::Identity();
  return f;
}

Matrix36d observation() {
  Matrix36d h = Matrix36d::Zero();
  h.leftCols<3>().setIdentity();
  return h;
}

TEST(ConstantVelocityFilter, StartsAtTheMeasurementWithZeroVelocity) {
  const ConstantVelocityModel model;
  const ConstantVelocityFilter filter(model, Gaussian3::from_covariance(Vector3d(1, 2, 3), Matrix3d::Identity()));
  EXPECT_EQ(filter.state().head<3>(), Vector3d(1, 2, 3));
  EXPECT_EQ(filter.state().tail<3>(), Vector3d::Zero());
  Vector6d diagonal;
  diagonal << Vector3d::Constant(10.0), Vector3d::Constant(1e6);
  EXPECT_EQ(filter.covariance(), Matrix6d(diagonal.asDiagonal()));
}

TEST(ConstantVelocityFilter, PredictIsFCFtPlusQ) {
  ConstantVelocityModel model;
  model.position_noise_density = 0.7;
  model.velocity_noise_density = 0.3;
  std::mt19937_64 rng(11);
  ConstantVelocityFilter filter(model, Gaussian3::from_covariance(Vector3d(1, 2, 3), Matrix3d::Identity()));
  // Move the filter to a state with cross-covariances.
  filter.predict(0.1);
  filter.update(Gaussian3::from_covariance(Vector3d(1.1, 2.0, 2.9), testing::random_spd(rng, 0.5)));
  const Vector6d state = filter.state();
  const Matrix6d covariance = filter.covariance();
  const double dt = 0.37;
  filter.predict(dt);
  Vector6d q_diagonal;
  q_diagonal << Vector3d::Constant(0.7 * dt), Vector3d::Constant(0.3 * dt);
  const Matrix6d f = transition(dt);
  EXPECT_LT((filter.state() - f * state).norm(), 1e-13);
  EXPECT_LT((filter.covariance() - (f * covariance * f.transpose() + Matrix6d(q_diagonal.asDiagonal()))).norm(),
            1e-10);
}

TEST(ConstantVelocityFilter, UpdateIsTheKalmanUpdateWithH) {
  std::mt19937_64 rng(12);
  ConstantVelocityFilter filter(ConstantVelocityModel{}, Gaussian3::from_covariance(Vector3d::Zero(), Matrix3d::Identity()));
  filter.predict(0.2);
  const Vector6d s = filter.state();
  const Matrix6d c = filter.covariance();
  const Gaussian3 z = Gaussian3::from_covariance(Vector3d(0.4, -0.2, 0.1), testing::random_spd(rng, 0.2));
  filter.update(z);
  const Matrix36d h = observation();
  const Eigen::Matrix<double, 6, 3> k = c * h.transpose() * (h * c * h.transpose() + z.covariance()).inverse();
  EXPECT_LT((filter.state() - (s + k * (z.mean() - h * s))).norm(), 1e-12);
  EXPECT_LT(testing::relative_difference(filter.covariance(), (Matrix6d::Identity() - k * h) * c), 1e-11);
}

// One update with all views equals one Kalman update per view, in any order.
TEST(ConstantVelocityFilter, ManyViewsAtOnceEqualsOneViewAtATime) {
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 50; ++trial) {
    const Gaussian3 start = Gaussian3::from_covariance(Vector3d::Random(), testing::random_spd(rng, 0.3));
    ConstantVelocityFilter batch(ConstantVelocityModel{}, start);
    ConstantVelocityFilter sequential(ConstantVelocityModel{}, start);
    batch.predict(0.1);
    sequential.predict(0.1);
    std::vector<Gaussian3> views;
    const int count = 1 + trial % 7;
    for (int u = 0; u < count; ++u) {
      views.push_back(Gaussian3::from_covariance(Vector3d::Random(), testing::random_spd(rng, 0.3)));
    }
    batch.update(views);
    for (const Gaussian3& view : views) sequential.update(view);
    ASSERT_LT((batch.state() - sequential.state()).norm(), 1e-10);
    ASSERT_LT(testing::relative_difference(batch.covariance(), sequential.covariance()), 1e-10);
  }
}

TEST(ConstantVelocityFilter, NoViewLeavesTheStateAlone) {
  ConstantVelocityFilter filter(ConstantVelocityModel{}, Gaussian3::from_covariance(Vector3d(1, 1, 1), Matrix3d::Identity()));
  const Vector6d before = filter.state();
  filter.update(std::span<const Gaussian3>{});
  EXPECT_EQ(filter.state(), before);
}

// Tracking a target at 1.5 m/s with small noise recovers its velocity at 2 Hz and at 10 Hz alike,
// because Q is a density (per second), not a per-frame constant.
TEST(ConstantVelocityFilter, RecoversVelocityAtAnyRate) {
  for (double rate : {2.0, 10.0, 30.0}) {
    std::mt19937_64 rng(14);
    std::normal_distribution<double> noise(0.0, 0.05);
    const Vector3d velocity(1.5, -0.5, 0.0);
    const Matrix3d r = 0.05 * 0.05 * Matrix3d::Identity();
    ConstantVelocityModel model;
    model.position_noise_density = 0.01;
    model.velocity_noise_density = 0.01;
    ConstantVelocityFilter filter(model, Gaussian3::from_covariance(Vector3d::Zero(), r));
    const int steps = static_cast<int>(20.0 * rate);  // 20 seconds
    for (int k = 1; k <= steps; ++k) {
      filter.predict(1.0 / rate);
      const Vector3d truth = velocity * (k / rate);
      filter.update(Gaussian3::from_covariance(truth + Vector3d(noise(rng), noise(rng), noise(rng)), r));
    }
    EXPECT_LT((filter.state().tail<3>() - velocity).norm(), 0.1) << "rate " << rate;
  }
}

TEST(ConstantVelocityFilter, RejectsNegativeStep) {
  ConstantVelocityFilter filter(ConstantVelocityModel{}, Gaussian3::from_covariance(Vector3d::Zero(), Matrix3d::Identity()));
  EXPECT_THROW(filter.predict(-0.1), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
