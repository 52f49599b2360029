// A track's prediction in continuous time (core/object_track.hpp): along one forecast the process
// noise grows as Q(τ) − Q(τ_s) between updates, so it adds up to Q(τ) however often the track is
// updated; history positions start only a history spacing apart.

#include "stgf/core/object_track.hpp"

#include <gtest/gtest.h>

namespace stgf {
namespace {

TEST(ObjectTrack, PredictsAlongTheForecastAndGrowsQByItsIncrement) {
  const ConstantVelocityPredictor predictor(/*q=*/2.0, /*speed=*/1.0, /*horizon=*/10.0, /*history_spacing=*/0.09);
  const ProcessNoiseScale scale;  // λ = 1
  const Matrix3d p = 0.01 * Matrix3d::Identity();
  ObjectTrack track;
  track.update(0.0, Gaussian3::from_covariance(Vector3d(0, 0, 0), p), predictor);
  track.update(0.1, Gaussian3::from_covariance(Vector3d(0.1, 0, 0), p), predictor);
  ASSERT_EQ(track.history().size(), 2u);
  ASSERT_TRUE(track.needs_forecast());
  track.set_forecast(predictor.forecast(std::vector<MotionGraph>{
      {"s", "", 0.2, {{"o", {Vector3d(0, 0, 0), Vector3d(0.1, 0, 0)}, {0.0, 0.1}}}}})[0][0]);
  // 0.13: 0.03 s after the last history position, from the state at 0.1.
  TrackPrediction first = track.predict(0.13, predictor, scale);
  EXPECT_LT((first.prior.mean() - Vector3d(0.13, 0, 0)).norm(), 1e-12);
  EXPECT_LT((first.prior.covariance() - (p + 2.0 * 0.03 * 0.03 * Matrix3d::Identity())).norm(), 1e-15);
  // An update 0.03 s later refines the state without a new history position (spacing 0.09).
  track.update(0.13, Gaussian3::from_covariance(Vector3d(0.135, 0, 0), p), predictor);
  EXPECT_EQ(track.history().size(), 2u);
  EXPECT_FALSE(track.needs_forecast());
  // To 0.16: from the state at 0.13 (τ_s = 0.03) along the same forecast to τ = 0.06.
  const TrackPrediction second = track.predict(0.16, predictor, scale);
  EXPECT_LT((second.prior.mean() - Vector3d(0.135 + 0.03, 0, 0)).norm(), 1e-12);
  const double increment = 2.0 * (0.06 * 0.06 - 0.03 * 0.03);
  EXPECT_LT((second.prior.covariance() - (p + increment * Matrix3d::Identity())).norm(), 1e-15);
  EXPECT_NEAR(second.interval * second.interval, 0.06 * 0.06 - 0.03 * 0.03, 1e-15);
  // The increments telescope: Q(0.03) + [Q(0.06) − Q(0.03)] = Q(0.06), as one update at 0.16 would add.
  EXPECT_NEAR(first.process_noise(0, 0) + second.process_noise(0, 0), 2.0 * 0.06 * 0.06, 1e-15);
  // A spacing after the last history position, an update starts a new one and drops the forecast.
  track.update(0.2, Gaussian3::from_covariance(Vector3d(0.2, 0, 0), p), predictor);
  EXPECT_EQ(track.history().size(), 2u);  // the CV predictor keeps two
  EXPECT_EQ(track.history().back().time, 0.2);
  EXPECT_TRUE(track.needs_forecast());
}

TEST(ObjectTrack, OneHistoryPositionAddsTheUnknownSpeedsSpread) {
  const ConstantVelocityPredictor predictor(1.0, /*speed=*/1.5);
  ObjectTrack track;
  const Matrix3d p = 0.04 * Matrix3d::Identity();
  track.update(1.0, Gaussian3::from_covariance(Vector3d(1, 2, 0), p), predictor);
  track.set_forecast(MotionForecast{});
  const TrackPrediction prediction = track.predict(1.2, predictor, ProcessNoiseScale{});
  EXPECT_EQ(prediction.prior.mean(), Vector3d(1, 2, 0));
  const double variance = 0.04 + 1.0 * 0.2 * 0.2 + 1.5 * 1.5 * 0.2 * 0.2;
  EXPECT_LT((prediction.prior.covariance() - variance * Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_THROW(track.predict(1.0, predictor, ProcessNoiseScale{}), std::logic_error);
}

}  // namespace
}  // namespace stgf
