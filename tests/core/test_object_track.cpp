// SPDX-License-Identifier: Apache-2.0
// A track in continuous time (core/object_track.hpp): predictions from its state along the forecast,
// the process noise grown by Q(τ) − Q(τ_s), so it adds up to Q(τ) however many updates came in
// between; a closed frame leaves the state as the next history position.

#include "stgf/core/object_track.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "stgf/core/eigenvalue_floor.hpp"
#include "support/test_predictors.hpp"

namespace stgf {
namespace {

// A frame with one update at its own time, closed: the update becomes a history position.
void add_history_position(ObjectTrack& track, double time, const Vector3d& z, const Matrix3d& p,
                          const MotionPredictor& predictor) {
  track.open_frame(time);
  track.update(time, Gaussian3::from_covariance(z, p));
  track.close_frame(predictor);
}

TEST(ObjectTrack, MovesMeasurementsAlongTheForecastAndGrowsQByItsIncrement) {
  const ConstantVelocityPredictor predictor(/*q=*/2.0, /*speed=*/1.0);
  const ProcessNoiseScale scale;  // λ = 1
  const Matrix3d p = 0.01 * Matrix3d::Identity();
  ObjectTrack track;
  add_history_position(track, 0.0, Vector3d(0, 0, 0), p, predictor);
  add_history_position(track, 0.1, Vector3d(0.1, 0, 0), p, predictor);  // 1 m/s along x
  ASSERT_EQ(track.history().size(), 2u);
  ASSERT_TRUE(track.needs_forecast());
  track.set_forecast(predictor.forecast(std::vector<MotionGraph>{
      {"s", "", 0.2, {{"o", {Vector3d(0, 0, 0), Vector3d(0.1, 0, 0)}, {0.0, 0.1}}}}})[0][0]);
  // The prediction to 0.13 (τ = 0.03); an update there opens a frame. Q alone (the history's velocity
  // error: below).
  const TrackPrediction first = track.predict(0.13, predictor, scale, /*constant_velocity=*/false, /*velocity_error=*/false);
  EXPECT_LT((first.prior.mean() - Vector3d(0.13, 0, 0)).norm(), 1e-12);
  EXPECT_LT((first.prior.covariance() - (p + 2.0 * 0.03 * 0.03 * Matrix3d::Identity())).norm(), 1e-15);
  track.open_frame(0.13);
  track.update(0.13, Gaussian3::from_covariance(Vector3d(0.135, 0, 0), p));
  // To 0.16: from the state at 0.13 (τ_s = 0.03) along the same forecast to τ = 0.06.
  const TrackPrediction second = track.predict(0.16, predictor, scale, false, false);
  EXPECT_LT((second.prior.mean() - Vector3d(0.135 + 0.03, 0, 0)).norm(), 1e-12);
  const double growth = 2.0 * (0.06 * 0.06 - 0.03 * 0.03);
  EXPECT_LT((second.prior.covariance() - (p + growth * Matrix3d::Identity())).norm(), 1e-15);
  EXPECT_NEAR(second.interval, 0.03, 1e-15);
  // The increments telescope: Q(0.03) + [Q(0.06) − Q(0.03)] = Q(0.06), as one update at 0.16 would add.
  EXPECT_NEAR(first.process_noise(0, 0) + second.process_noise(0, 0), 2.0 * 0.06 * 0.06, 1e-15);
  // The motion alone, as the joint estimate of positions and offsets applies it.
  const ObjectTrack::Motion motion = track.motion_to(0.16, predictor, scale, false, false);
  EXPECT_LT((motion.displacement - Vector3d(0.03, 0, 0)).norm(), 1e-12);
  EXPECT_LT((motion.covariance - growth * Matrix3d::Identity()).norm(), 1e-15);
  track.update(0.16, Gaussian3::from_covariance(Vector3d(0.166, 0, 0), p));
  // Closing makes the state (at 0.16, with every measurement of the frame) the next history position.
  EXPECT_FALSE(track.needs_forecast());
  track.close_frame(predictor);
  EXPECT_EQ(track.history().size(), 2u);  // the constant-velocity predictor keeps two
  EXPECT_EQ(track.history().back().time, 0.16);
  EXPECT_TRUE(track.needs_forecast());
  EXPECT_FALSE(track.has_frame());
}

class KeepsThreePositions final : public testing::ForwardingPredictor {
 public:
  KeepsThreePositions() : ForwardingPredictor(2.0, 1.0, 1.0) {}
  int history_positions() const override { return 3; }
};

// The velocity a forecast reads from the history carries the positions' errors on (object_track.hpp):
// ΔJ V ΔJ + ΔJ K_s + K_sᵀ ΔJ, with V = Var(v̂) of the least-squares slope of the positions, (P̂_1 + P̂_2) /
// Δt² for two, and K_s its covariance with the state's error.
TEST(ObjectTrack, ForecastCountsTheErrorOfTheVelocityItReadsFromTheHistory) {
  const ConstantVelocityPredictor predictor(/*q=*/2.0, /*speed=*/1.0);
  const ProcessNoiseScale scale;
  const Matrix3d p1 = Vector3d(0.01, 0.02, 0.03).asDiagonal(), p2 = Vector3d(0.04, 0.01, 0.02).asDiagonal();
  ObjectTrack track;
  add_history_position(track, 0.0, Vector3d(0, 0, 0), p1, predictor);
  add_history_position(track, 0.1, Vector3d(0.1, 0, 0), p2, predictor);
  EXPECT_LT((track.velocity_variance(/*last_two=*/false) - (p1 + p2) / 0.01).norm(), 1e-12);
  track.set_forecast(predictor.forecast(std::vector<MotionGraph>{
      {"s", "", 0.2, {{"o", {Vector3d(0, 0, 0), Vector3d(0.1, 0, 0)}, {0.0, 0.1}}}}})[0][0]);
  const ObjectTrack::Motion motion = track.motion_to(0.15, predictor, scale);
  // τ² V + τ (K_n + K_nᵀ): the last position's error is in the slope's too, K_n = w_2 P̂_2 = P̂_2 / Δt (the
  // positions' errors independent here).
  EXPECT_LT((track.velocity_position_covariance(false) - p2 / 0.1).norm(), 1e-12);
  const Matrix3d velocity_error = 0.05 * 0.05 * (p1 + p2) / 0.01 + 0.05 * 2.0 * p2 / 0.1;
  EXPECT_LT((track.velocity_error_to(0.15, false) - velocity_error).norm(), 1e-12);
  EXPECT_LT((motion.covariance - (2.0 * 0.05 * 0.05 * Matrix3d::Identity() + velocity_error)).norm(), 1e-12);
  // The prediction carries it; constant velocity's from the last two positions (the same two here).
  const TrackPrediction prediction = track.predict(0.15, predictor, scale);
  EXPECT_LT((prediction.prior.covariance() - (p2 + motion.covariance)).norm(), 1e-12);
  EXPECT_LT((track.motion_to(0.15, predictor, scale, /*constant_velocity=*/true).covariance - motion.covariance).norm(), 1e-12);
  // From a state at 0.15 whose error owes nothing to the history (an update that kept nothing of its
  // prior: G_s = 0), to 0.2: the slope's error from there on alone, (τ − τ_s)² V.
  track.open_frame(0.15);
  track.update(0.15, Gaussian3::from_covariance(Vector3d(0.15, 0, 0), p2));
  EXPECT_LT((track.velocity_error_to(0.2, false) - 0.05 * 0.05 * (p1 + p2) / 0.01).norm(), 1e-12);
  // A forecast that does not carry the slope on (J = 0) adds nothing for it; one that brings the
  // position back against it (J_x = −τ) takes the last position's share of the slope's error away.
  ObjectTrack still;
  add_history_position(still, 0.0, Vector3d(0, 0, 0), p1, predictor);
  add_history_position(still, 0.1, Vector3d(0.1, 0, 0), p2, predictor);
  MotionForecast ignores;
  ignores.velocity_response = Vector3d::Zero();
  still.set_forecast(ignores);
  EXPECT_EQ(still.velocity_error_to(0.15, false), Matrix3d::Zero());
  EXPECT_LT((still.velocity_error_to(0.15, true) - velocity_error).norm(), 1e-12);  // constant velocity's: τ
  MotionForecast reverts;
  reverts.velocity_response = Vector3d(-1.0, 1.0, 1.0);
  still.set_forecast(reverts);
  const Matrix3d reverting = still.velocity_error_to(0.15, false);
  EXPECT_NEAR(reverting(0, 0), 0.25 * (p1(0, 0) + p2(0, 0)) - p2(0, 0), 1e-12);  // 0.0125 − 0.04: negative
  EXPECT_NEAR(reverting(1, 1), velocity_error(1, 1), 1e-12);

  // Three positions 0.1 s apart: w = (−5, 0, 5) per second, Var(v̂) = 25 (P̂_1 + P̂_3); the last two alone
  // (constant velocity, coasting): (P̂_2 + P̂_3) / Δt².
  ObjectTrack three;
  const KeepsThreePositions keeps_three;
  add_history_position(three, 0.0, Vector3d(0, 0, 0), p1, keeps_three);
  add_history_position(three, 0.1, Vector3d(0.1, 0, 0), p2, keeps_three);
  add_history_position(three, 0.2, Vector3d(0.2, 0, 0), p1, keeps_three);
  ASSERT_EQ(three.history().size(), 3u);
  EXPECT_LT((three.velocity_variance(false) - 25.0 * (p1 + p1)).norm(), 1e-12);
  EXPECT_LT((three.velocity_variance(true) - (p2 + p1) / 0.01).norm(), 1e-12);
  // One position or none: no velocity, no error of it (the unknown speed's spread stands for it).
  ObjectTrack one;
  add_history_position(one, 0.0, Vector3d(0, 0, 0), p1, predictor);
  EXPECT_EQ(one.velocity_variance(false), Matrix3d::Zero());
}

// A change of a covariance that takes variance away is held so that the sum keeps half of the
// covariance's least variance; a covariance change passes as it is.
TEST(ObjectTrack, AChangeThatTakesVarianceAwayKeepsHalfTheLeastVariance) {
  const Matrix3d covariance = Vector3d(0.04, 0.01, 0.02).asDiagonal();
  const Matrix3d growth = Vector3d(0.01, 0.0, 0.3).asDiagonal();
  EXPECT_EQ(grown_within(covariance, growth), growth);
  const Matrix3d small_loss = Vector3d(-0.02, 0.0, 0.0).asDiagonal();  // leaves 0.02 ≥ 0.005
  EXPECT_EQ(grown_within(covariance, small_loss), small_loss);
  const Matrix3d loss = Vector3d(-0.039, 0.0, 0.001).asDiagonal();  // would leave 0.001
  const Matrix3d held = grown_within(covariance, loss);
  EXPECT_LT((covariance + held - Matrix3d(Vector3d(0.005, 0.01, 0.021).asDiagonal())).norm(), 1e-15);
}

class KeepsEightPositions final : public testing::ForwardingPredictor {
 public:
  KeepsEightPositions() : ForwardingPredictor(2.0, 1.0, 1.0) {}
  int history_positions() const override { return 8; }
};

// A Kalman filter on a random walk (steps of covariance m, measurements of covariance r, dt apart), its
// estimates the history positions of a track, run `runs` times from an error N(0, p0): the velocity
// variance the track counts, the one measured (of the least-squares slope of the estimates' errors),
// and the one counted with the positions' errors independent; the slope's error's covariance with the
// last position's, counted and measured; and the covariance of a prediction 0.1 s on by a forecast that
// carries the slope on (J = τ) and by one that brings it back (J = −τ), counted (P̂_n and the slope's
// terms) and measured (of e_n ± τ δv).
struct SlopeErrors {
  Matrix3d counted = Matrix3d::Zero(), measured = Matrix3d::Zero(), independent = Matrix3d::Zero();
  Matrix3d counted_with_last = Matrix3d::Zero(), measured_with_last = Matrix3d::Zero();
  Matrix3d counted_ahead = Matrix3d::Zero(), measured_ahead = Matrix3d::Zero();
  Matrix3d counted_back = Matrix3d::Zero(), measured_back = Matrix3d::Zero();
};
SlopeErrors filter_random_walk(const Matrix3d& m, const Matrix3d& r, const Matrix3d& p0, int runs) {
  const KeepsEightPositions predictor;
  const int steps = predictor.history_positions();
  const double dt = 0.1;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  const Eigen::LLT<Matrix3d> m_root(m), r_root(r), p0_root(p0);
  const auto draw = [&](const Eigen::LLT<Matrix3d>& root) {
    return Vector3d(root.matrixL() * Vector3d(normal(rng), normal(rng), normal(rng)));
  };
  std::vector<double> w(steps);  // w_i = (t_i − t̄) / Σ (t_j − t̄)²
  double spread = 0.0;
  for (int i = 0; i < steps; ++i) spread += (i - 3.5) * (i - 3.5) * dt * dt;
  for (int i = 0; i < steps; ++i) w[i] = (i - 3.5) * dt / spread;
  SlopeErrors errors;
  for (int run = 0; run < runs; ++run) {
    ObjectTrack track;
    Vector3d truth = Vector3d::Zero(), slope_error = Vector3d::Zero();
    Vector3d mean = truth + draw(p0_root);
    Matrix3d p = p0;
    for (int k = 0; k < steps; ++k) {
      track.open_frame(k * dt);
      if (k == 0) {
        track.update(0.0, Gaussian3::from_covariance(mean, p));
      } else {
        truth += draw(m_root);
        const Vector3d z = truth + draw(r_root);
        const Matrix3d prior = p + m;
        const Matrix3d gain = prior * (prior + r).inverse();
        mean += gain * (z - mean);
        p = symmetrised((Matrix3d::Identity() - gain) * prior);
        track.update(k * dt, Gaussian3::from_covariance(mean, p), prior);
      }
      track.close_frame(predictor);
      slope_error += w[k] * (mean - truth);
    }
    errors.measured += slope_error * slope_error.transpose() / runs;
    const Vector3d last_error = mean - truth, ahead = last_error + 0.1 * slope_error, back = last_error - 0.1 * slope_error;
    errors.measured_with_last += slope_error * last_error.transpose() / runs;
    errors.measured_ahead += ahead * ahead.transpose() / runs;
    errors.measured_back += back * back.transpose() / runs;
    if (run == 0) {  // the filter's covariances are the same on every run
      errors.counted = track.velocity_variance(/*last_two=*/false);
      errors.counted_with_last = track.velocity_position_covariance(false);
      const double next = (steps - 1) * dt + 0.1;
      errors.counted_ahead = p + track.velocity_error_to(next, false);  // no forecast: J = τ
      MotionForecast brings_back;
      brings_back.velocity_response = -Vector3d::Ones();
      track.set_forecast(brings_back);
      errors.counted_back = p + track.velocity_error_to(next, false);
      for (int i = 0; i < steps; ++i) errors.independent += w[i] * w[i] * track.history()[i].estimate.covariance();
    }
  }
  return errors;
}

void expect_counted_as_measured(const SlopeErrors& errors) {
  for (int a = 0; a < 3; ++a) {  // 20000 runs: ±1 % (1σ)
    EXPECT_NEAR(errors.counted(a, a) / errors.measured(a, a), 1.0, 0.04) << "axis " << a;
  }
  EXPECT_NEAR(errors.counted(0, 1), errors.measured(0, 1),
              0.05 * std::sqrt(errors.measured(0, 0) * errors.measured(1, 1)));
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(errors.counted_with_last(a, a), errors.measured_with_last(a, a),
                0.05 * std::sqrt(errors.measured(a, a) * errors.measured_ahead(a, a)))
        << "axis " << a;
    EXPECT_NEAR(errors.counted_ahead(a, a) / errors.measured_ahead(a, a), 1.0, 0.04) << "axis " << a;
    EXPECT_NEAR(errors.counted_back(a, a) / errors.measured_back(a, a), 1.0, 0.04) << "axis " << a;
  }
}

// Successive history positions of a filter share their errors: each is the one before, predicted and
// pulled toward a measurement, e_k = G_k e_{k−1} + (independent), G_k = P⁺ (P⁻)⁻¹. Var(v̂) counts that
// correlation (object_track.hpp), on a track that starts from a measurement and on one settled, and so
// do its covariance with the last position's error and a prediction's (J = ±τ). Counted
// independent, the slope's error is about 40 % too small on the moving axes, and once settled several
// times too large on the heights (a tiny vertical Q, as a ground plane's: smoothed over many steps).
TEST(ObjectTrack, VelocityErrorCountsTheShareOfEachPositionsErrorThatTheNextCarries) {
  const Matrix3d m = Vector3d(0.01, 0.02, 1e-5).asDiagonal();
  Matrix3d r;
  r << 0.04, 0.01, 0.0, 0.01, 0.03, 0.0, 0.0, 0.0, 0.02;
  const int runs = 20000;
  // From one measurement.
  expect_counted_as_measured(filter_random_walk(m, r, r, runs));
  // Settled: from the filter's steady covariance (the error is then stationary).
  Matrix3d steady = r;
  for (int k = 0; k < 10000; ++k) {
    const Matrix3d prior = steady + m;
    steady = symmetrised(prior - prior * (prior + r).inverse() * prior);
  }
  const SlopeErrors settled = filter_random_walk(m, r, steady, runs);
  expect_counted_as_measured(settled);
  EXPECT_GT(settled.independent(2, 2), 3.0 * settled.measured(2, 2));
  EXPECT_LT(settled.independent(0, 0), 0.8 * settled.measured(0, 0));
  // The slope's error shares the last position's: a forecast that brings the position back against
  // the slope is more certain than the state it starts from, on every axis here.
  for (int a = 0; a < 3; ++a) EXPECT_LT(settled.measured_back(a, a), settled.measured_ahead(a, a)) << "axis " << a;
}

TEST(ObjectTrack, CoastsAcrossOneMissedFrameAtItsOwnRateWhenThePredictorCoasts) {
  const testing::CoastingPredictor predictor(/*horizon=*/0.6, /*coasting_horizon=*/0.8);
  const Matrix3d p = 0.01 * Matrix3d::Identity();
  ObjectTrack track;
  add_history_position(track, 0.0, Vector3d::Zero(), p, predictor);
  EXPECT_FALSE(track.frame_interval().has_value());
  EXPECT_EQ(track.unseen_limit(predictor), 0.8);  // no frame interval known
  EXPECT_EQ(track.unseen_limit(predictor, /*scene_frame_interval=*/0.4), 1.0);  // the scene's
  add_history_position(track, 0.5, Vector3d::Zero(), p, predictor);
  EXPECT_EQ(track.frame_interval(), 0.5);
  EXPECT_EQ(track.unseen_limit(predictor), 1.25);  // 2.5 frames of 0.5 s: one missed frame, with room
  EXPECT_EQ(track.unseen_limit(predictor, 0.4), 1.25);  // its own interval before the scene's
  ObjectTrack fast;
  add_history_position(fast, 0.0, Vector3d::Zero(), p, predictor);
  add_history_position(fast, 0.1, Vector3d::Zero(), p, predictor);
  EXPECT_EQ(fast.unseen_limit(predictor), 0.8);  // the coasting horizon is the longer
  // A predictor that does not coast: its horizon, whatever the frame interval.
  const ConstantVelocityPredictor plain(1.0, 1.0, /*horizon=*/0.6);
  EXPECT_EQ(track.unseen_limit(plain, 0.4), 0.6);
}

TEST(ObjectTrack, OneHistoryPositionAddsTheUnknownSpeedsSpread) {
  const ConstantVelocityPredictor predictor(1.0, /*speed=*/1.5);
  ObjectTrack track;
  const Matrix3d p = 0.04 * Matrix3d::Identity();
  add_history_position(track, 1.0, Vector3d(1, 2, 0), p, predictor);
  track.set_forecast(MotionForecast{});
  const TrackPrediction prediction = track.predict(1.2, predictor, ProcessNoiseScale{});
  EXPECT_EQ(prediction.prior.mean(), Vector3d(1, 2, 0));
  const double variance = 0.04 + 1.0 * 0.2 * 0.2 + 1.5 * 1.5 * 0.2 * 0.2;
  EXPECT_LT((prediction.prior.covariance() - variance * Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_THROW(track.predict(1.0, predictor, ProcessNoiseScale{}), std::logic_error);
  // Without any history, a prediction keeps the position, with the unknown speed's spread and Q.
  ObjectTrack fresh;
  fresh.update(0.0, Gaussian3::from_covariance(Vector3d(1, 2, 0), p));
  const TrackPrediction standing = fresh.predict(0.1, predictor, ProcessNoiseScale{});
  EXPECT_EQ(standing.prior.mean(), Vector3d(1, 2, 0));
  EXPECT_LT((standing.prior.covariance() - (0.04 + 0.01 + 1.5 * 1.5 * 0.01) * Matrix3d::Identity()).norm(), 1e-15);
}

}  // namespace
}  // namespace stgf
