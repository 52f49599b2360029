// SPDX-License-Identifier: Apache-2.0
// Calibrating Q in the filter's own regime (learn/filter_calibration.hpp) with an untrained Φ on
// small synthetic scenes: every round's Q is a covariance, the last round's prior NEES is near 3, the
// model keeps the last Q, the rounds are reproducible, and bad arguments are rejected.

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "stgf/learn/filter_calibration.hpp"
#include "stgf/methods/filter_runner.hpp"
#include "stgf/methods/run_method.hpp"
#include "stgf/methods/weighted_least_squares.hpp"
#include "support/tiny_motion_model.hpp"

namespace stgf {
namespace {

constexpr int kScenes = 20;
constexpr int kSteps = 12;
constexpr int kLongSteps = 40;  // scenes long enough to thin out to a frame every 0.8 s
constexpr int kObjects = 3;
constexpr int kViews = 3;
constexpr double kPeriod = 0.1;

using stgf::testing::tiny_shape;

struct Scenes {
  std::vector<Measurement> measurements;
  std::vector<Vector3d> truth;
};

// Objects moving at a nearly constant velocity (about 1 m/s, velocity jittered by 0.3 m/s² white
// acceleration), every view measuring every object at every step with its own isotropic noise.
Scenes constant_velocity_scenes(std::uint64_t seed, int steps = kSteps) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::vector<double> view_sigma = {0.05, 0.1, 0.2};
  Scenes scenes;
  for (int scene = 0; scene < kScenes; ++scene) {
    std::vector<Vector3d> position, velocity;
    for (int object = 0; object < kObjects; ++object) {
      position.emplace_back(20.0 * unit(rng) - 10.0, 20.0 * unit(rng) - 10.0, 0.0);
      const double heading = 6.283 * unit(rng);
      velocity.emplace_back(std::cos(heading), std::sin(heading), 0.0);
    }
    for (int step = 0; step < steps; ++step) {
      const double time = 5.0 + kPeriod * step;
      for (int object = 0; object < kObjects; ++object) {
        if (step > 0) {
          velocity[object] +=
              0.3 * std::sqrt(kPeriod) * Vector3d(normal(rng), normal(rng), 0.1 * normal(rng));
          position[object] += velocity[object] * kPeriod;
        }
        for (int view = 0; view < kViews; ++view) {
          const double sigma = view_sigma[view];
          const Vector3d z = position[object] + sigma * Vector3d(normal(rng), normal(rng), normal(rng));
          scenes.measurements.push_back(
              Measurement{"scene" + std::to_string(scene), time, "view" + std::to_string(view),
                          "o" + std::to_string(object),
                          Gaussian3::from_covariance(z, sigma * sigma * Matrix3d::Identity()), std::nullopt, std::nullopt});
          scenes.truth.push_back(position[object]);
        }
      }
    }
  }
  return scenes;
}

MotionModel untrained_model() { return MotionModel(tiny_shape(), MotionNormalisation{1.0, kPeriod, 5.0}, 3); }

TEST(FilterCalibration, CalibratesAConsistentProcessNoise) {
  const Scenes scenes = constant_velocity_scenes(7);
  MotionModel model = untrained_model();
  const FilterCalibration calibration =
      calibrate_filter_process_noise(model, RegistrationPrior{}, scenes.measurements, scenes.truth, {}, 5);
  ASSERT_EQ(calibration.rounds.size(), 5u);
  EXPECT_NEAR(calibration.period, kPeriod, 1e-9);
  // Every view predicts every object from the third step on (a track of two positions or more).
  EXPECT_EQ(calibration.predictions, static_cast<std::size_t>(kScenes * (kSteps - 2) * kObjects * kViews));
  for (std::size_t round = 0; round < calibration.rounds.size(); ++round) {
    const FilterCalibrationRound& report = calibration.rounds[round];
    const Matrix3d& q = report.process_noise;
    EXPECT_TRUE(q.allFinite()) << "round " << round;
    EXPECT_EQ(q, q.transpose()) << "round " << round;
    const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(q);
    EXPECT_GT(eigen.eigenvalues().minCoeff(), 0.0) << "round " << round << "\n" << q;
    EXPECT_TRUE(std::isfinite(report.prior_nees) && report.prior_nees > 0.0) << "round " << round;
    EXPECT_GT(report.prior_error, 0.0);
    EXPECT_LT(report.prior_error, 1.0);
    EXPECT_TRUE(report.stable) << "round " << round;
  }
  const FilterCalibrationRound& last = calibration.rounds.back();
  EXPECT_GE(last.prior_nees, 2.0);
  EXPECT_LE(last.prior_nees, 4.5);
  // The check runs the last Q: stable, and as consistent.
  EXPECT_TRUE(calibration.check.stable);
  EXPECT_EQ(calibration.check.process_noise, last.process_noise);
  EXPECT_GE(calibration.check.prior_nees, 2.0);
  EXPECT_LE(calibration.check.prior_nees, 4.5);
  // The model keeps the last round's Q, at the calibration's reference period.
  EXPECT_EQ(model.process_noise(calibration.period), last.process_noise);
  EXPECT_LT((model.process_noise(2.0 * calibration.period) - 4.0 * last.process_noise).cwiseAbs().maxCoeff(),
            1e-15);
}

// Without truth, against the fused measurement of each row's object and time (its covariance taken
// out), Q comes out as against the truth: the same predictions, the same scale.
TEST(FilterCalibration, TheFusedMeasurementsStandInForTheTruth) {
  const Scenes scenes = constant_velocity_scenes(7);
  MotionModel against_truth = untrained_model();
  MotionModel against_measurements = untrained_model();
  const FilterCalibration truth =
      calibrate_filter_process_noise(against_truth, RegistrationPrior{}, scenes.measurements, scenes.truth, {}, 5);
  std::vector<Vector3d> targets;
  std::vector<Matrix3d> covariances;
  const auto wls = [] { return std::make_unique<WeightedLeastSquares>(); };
  for (const Gaussian3& fused : run_localizer(wls, scenes.measurements)) {
    targets.push_back(fused.mean());
    covariances.push_back(fused.covariance());
  }
  const FilterCalibration measured = calibrate_filter_process_noise(against_measurements, RegistrationPrior{},
                                                                    scenes.measurements, targets, covariances, 5);
  const Matrix3d& q_truth = truth.rounds.back().process_noise;
  const Matrix3d& q_measured = measured.rounds.back().process_noise;
  for (int axis = 0; axis < 2; ++axis) {  // the horizontal axes, where the motion is
    EXPECT_NEAR(q_measured(axis, axis), q_truth(axis, axis), 0.25 * q_truth(axis, axis)) << q_measured << "\n\n" << q_truth;
  }
  EXPECT_GE(measured.rounds.back().prior_nees, 2.0);
  EXPECT_LE(measured.rounds.back().prior_nees, 4.5);
  // Without taking the target's covariance out, Q would absorb the measurement noise.
  MotionModel uncorrected = untrained_model();
  const FilterCalibration biased =
      calibrate_filter_process_noise(uncorrected, RegistrationPrior{}, scenes.measurements, targets, {}, 5);
  EXPECT_GT(biased.rounds.back().process_noise.trace(), 1.1 * q_measured.trace());
}

// Each round depends only on the previous one, so two rounds from a fresh model repeat the first two
// rounds of a longer run exactly.
TEST(FilterCalibration, IsDeterministic) {
  const Scenes scenes = constant_velocity_scenes(11);
  MotionModel first = untrained_model();
  MotionModel second = untrained_model();
  const FilterCalibration a =
      calibrate_filter_process_noise(first, RegistrationPrior{}, scenes.measurements, scenes.truth, {}, 3);
  const FilterCalibration b =
      calibrate_filter_process_noise(second, RegistrationPrior{}, scenes.measurements, scenes.truth, {}, 2);
  ASSERT_EQ(a.rounds.size(), 3u);
  ASSERT_EQ(b.rounds.size(), 2u);
  EXPECT_EQ(a.period, b.period);
  EXPECT_EQ(a.predictions, b.predictions);
  for (std::size_t round = 0; round < b.rounds.size(); ++round) {
    EXPECT_EQ(a.rounds[round].prior_nees, b.rounds[round].prior_nees) << "round " << round;
    EXPECT_EQ(a.rounds[round].prior_error, b.rounds[round].prior_error) << "round " << round;
    EXPECT_EQ(a.rounds[round].process_noise, b.rounds[round].process_noise) << "round " << round;
  }
  // The round after moves Q half way to what it measured, so it differs from the one before.
  EXPECT_NE(a.rounds[2].process_noise, a.rounds[1].process_noise);
}

TEST(FilterCalibration, RejectsBadArguments) {
  const Scenes scenes = constant_velocity_scenes(13);
  MotionModel model = untrained_model();
  const Matrix3d before = model.process_noise(kPeriod);
  EXPECT_THROW(
      calibrate_filter_process_noise(model, RegistrationPrior{}, scenes.measurements, scenes.truth, {}, 0),
      std::invalid_argument);
  EXPECT_THROW(
      calibrate_filter_process_noise(model, RegistrationPrior{}, scenes.measurements, scenes.truth, {}, -1),
      std::invalid_argument);
  const std::vector<Vector3d> short_truth(scenes.truth.begin(), scenes.truth.end() - 1);
  EXPECT_THROW(
      calibrate_filter_process_noise(model, RegistrationPrior{}, scenes.measurements, short_truth, {}, 1),
      std::invalid_argument);
  // Tracks of one position only: nothing to calibrate on.
  const std::vector<Measurement> first_step(scenes.measurements.begin(),
                                            scenes.measurements.begin() + kObjects * kViews);
  const std::vector<Vector3d> first_truth(scenes.truth.begin(), scenes.truth.begin() + kObjects * kViews);
  EXPECT_THROW(calibrate_filter_process_noise(model, RegistrationPrior{}, first_step, first_truth, {}, 1),
               std::invalid_argument);
  EXPECT_EQ(model.process_noise(kPeriod), before);  // a rejected call leaves Q alone
}

// Every `stride`-th step of each scene, leaving out the step `skipped` (counted after thinning) of
// each scene: a lower frame rate with one missed frame.
// Every `stride`-th frame, without `missed` of them from the `skipped`-th on.
Scenes thinned(const Scenes& scenes, int stride, int skipped, int missed = 1) {
  Scenes result;
  for (std::size_t k = 0; k < scenes.measurements.size(); ++k) {
    const auto step = static_cast<int>(std::lround((scenes.measurements[k].time - 5.0) / kPeriod));
    if (step % stride != 0 || (step / stride >= skipped && step / stride < skipped + missed)) continue;
    result.measurements.push_back(scenes.measurements[k]);
    result.truth.push_back(scenes.truth[k]);
  }
  return result;
}

// Q at longer intervals. The objects move at a nearly constant velocity and Φ is untrained: at a
// frame every 0.2 s constant velocity predicts better than Φ, so every node is of the coasting curve
// (Φ's would have gone up to 1.25 times the longest interval it trained on, 0.375 s), Φ forecasts
// only from histories spaced up to √(0.1 · 0.2) s, and each node is a covariance, growing along the
// curve, which the model keeps. Then at a frame every 0.5 s with one frame missed (a gap of 1 s,
// beyond Φ's horizon of 0.6 s) no track starts again, and the estimates stay honest; without the
// nodes every track starts again after the missed frame. With two frames missed (1.5 s, beyond 2.5
// frame intervals but within the coasting horizon, ObjectTrack::unseen_limit) still none does.
TEST(FilterCalibration, CalibratesLongerIntervalsSoThatTracksCoastAcrossAMissedFrame) {
  const Scenes scenes = constant_velocity_scenes(7, kLongSteps);
  MotionModel model = untrained_model();
  calibrate_filter_process_noise(model, RegistrationPrior{}, scenes.measurements, scenes.truth, {}, 3);
  const MotionModel without = untrained_model();
  const double horizon = model.prediction_horizon();
  ASSERT_NEAR(horizon, 0.6, 1e-12);
  const IntervalCalibrations calibrated =
      calibrate_process_noise_intervals(model, RegistrationPrior{}, scenes.measurements, scenes.truth, {}, 0.8);
  EXPECT_EQ(calibrated.diverged_at, 0.0);
  const std::vector<IntervalCalibration>& nodes = calibrated.nodes;
  ASSERT_EQ(nodes.size(), 5u);
  const std::vector<double> intervals = {0.2, 0.3, 0.4, 0.6, 0.8};
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    EXPECT_NEAR(nodes[k].interval, intervals[k], 1e-12);
    EXPECT_TRUE(nodes[k].coasting) << k;
    EXPECT_GE(nodes[k].predictions, kMinimumIntervalPredictions);
    const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(nodes[k].process_noise);
    EXPECT_GT(eigen.eigenvalues().minCoeff(), 0.0) << k;
    if (k > 0) {
      const Eigen::SelfAdjointEigenSolver<Matrix3d> growth(nodes[k].process_noise - nodes[k - 1].process_noise);
      EXPECT_GE(growth.eigenvalues().minCoeff(), -1e-12) << k;
    }
  }
  // Both were run at 0.2 s only: Φ's error there is the larger.
  EXPECT_GT(nodes[0].prior_error, 0.0);
  EXPECT_GT(nodes[0].rival_error, nodes[0].prior_error);
  for (std::size_t k = 1; k < nodes.size(); ++k) EXPECT_EQ(nodes[k].rival_error, 0.0) << k;
  ASSERT_EQ(model.process_noise_intervals().size(), 0u);
  ASSERT_EQ(model.coasting_process_noise_intervals().size(), 5u);
  EXPECT_LT((model.coasting_process_noise(0.6) - nodes[3].process_noise).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_NEAR(model.coasting_horizon(), 1.6, 1e-12);
  EXPECT_NEAR(model.widest_history_spacing(), std::sqrt(0.1 * 0.2), 1e-12);
  EXPECT_EQ(model.prediction_horizon(), horizon);

  const Scenes low_rate = thinned(constant_velocity_scenes(8, kLongSteps), 5, 3);
  FilterOptions options;
  const FilterRun coasting = run_spatiotemporal_graph_filter(model, options, low_rate.measurements);
  const FilterRun restarting = run_spatiotemporal_graph_filter(without, options, low_rate.measurements);
  EXPECT_EQ(coasting.restarted_tracks, 0u);
  EXPECT_EQ(restarting.restarted_tracks, static_cast<std::size_t>(kScenes * kObjects));
  double nees = 0.0;
  for (std::size_t k = 0; k < low_rate.measurements.size(); ++k) {
    nees += coasting.estimates[k].mahalanobis_squared(low_rate.truth[k]);
  }
  nees /= static_cast<double>(low_rate.measurements.size());
  EXPECT_GT(nees, 2.0);
  EXPECT_LT(nees, 4.5);

  const Scenes two_missed = thinned(constant_velocity_scenes(8, kLongSteps), 5, 3, 2);
  EXPECT_EQ(run_spatiotemporal_graph_filter(model, options, two_missed.measurements).restarted_tracks, 0u);
}

}  // namespace
}  // namespace stgf
