// SPDX-License-Identifier: Apache-2.0
// A forecast's response to its history's slope (core/slope_response.hpp): the tilted histories, the
// response read from a second pass, and the filter asking for that pass.

#include "stgf/core/slope_response.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "stgf/core/scene_filter.hpp"
#include "support/test_predictors.hpp"

namespace stgf {
namespace {

MotionGraph two_objects() {
  return MotionGraph{"s", "", 1.0,
                     {{"a", {Vector3d(0, 0, 1), Vector3d(0.1, 0, 1), Vector3d(0.2, 0.05, 1)}, {0.0, 0.1, 0.2}},
                      {"b", {Vector3d(5, 5, 0), Vector3d(5, 5.1, 0)}, {0.3, 0.4}}}};
}

TEST(SlopeResponse, TiltsEachHistoryAboutItsLastPosition) {
  const MotionGraph graph = two_objects();
  const std::vector<Vector3d> tilts{Vector3d(0.1, 0.2, 0.3), Vector3d(1.0, 0.0, 0.0)};
  const MotionGraph tilted = tilted_graph(graph, tilts);
  ASSERT_EQ(tilted.objects.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const ObjectHistory& before = graph.objects[i];
    const ObjectHistory& after = tilted.objects[i];
    EXPECT_EQ(after.times, before.times);
    EXPECT_EQ(after.positions.back(), before.positions.back());
    for (std::size_t k = 0; k < before.positions.size(); ++k) {
      const Vector3d expected = before.positions[k] + tilts[i] * (before.times[k] - before.times.back());
      EXPECT_LT((after.positions[k] - expected).norm(), 1e-15);
    }
  }
  EXPECT_THROW(tilted_graph(graph, std::vector<Vector3d>{Vector3d::Ones()}), std::invalid_argument);
}

TEST(SlopeResponse, TiltIsTheSlopesOwnErrorWithinAHundredthOfTheTypicalSpeedAndIt) {
  const Matrix3d variance = Vector3d(0.04, 1e-12, 9.0).asDiagonal();
  EXPECT_LT((slope_tilt(variance, 1.5) - Vector3d(0.2, 0.015, 1.5)).norm(), 1e-15);
}

// Constant velocity carries the slope on as it is (J = τ); a forecast that ignores its history's
// motion does not carry it at all.
TEST(SlopeResponse, ConstantVelocityCarriesTheSlopeOnAsItIs) {
  const ConstantVelocityPredictor predictor(1.0, 1.0);
  const std::vector<MotionGraph> graphs{two_objects()};
  const std::vector<Vector3d> tilts{Vector3d(0.1, 0.2, 0.3), Vector3d(0.05, 0.05, 0.05)};
  const std::vector<MotionGraph> tilted{tilted_graph(graphs[0], tilts)};
  const auto plain = predictor.forecast(graphs), moved = predictor.forecast(tilted);
  for (std::size_t i = 0; i < 2; ++i) {
    const MotionForecast forecast = with_slope_response(plain[0][i], moved[0][i], tilts[i]);
    EXPECT_LT((forecast.velocity_response - Vector3d::Ones()).norm(), 1e-12);
    EXPECT_LT(forecast.acceleration_response.norm(), 1e-12);
    EXPECT_LT((forecast.slope_response(0.3) - Vector3d::Constant(0.3)).norm(), 1e-12);
    EXPECT_EQ(forecast.velocity, plain[0][i].velocity);  // the forecast itself is the untilted one's
  }
  MotionForecast still;  // velocity zero whatever the history
  const MotionForecast ignores = with_slope_response(still, still, tilts[0]);
  EXPECT_EQ(ignores.slope_response(0.3), Vector3d::Zero());
}

// A predictor whose vertical forecast brings the height back against its history's slope: v_z = −2 ×
// (the last two positions' vertical slope); horizontally constant velocity.
class BringsHeightsBack final : public testing::ForwardingPredictor {
 public:
  BringsHeightsBack() : ForwardingPredictor(0.01, 1.0, 10.0, /*history_spacing=*/0.09) {}
  std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const override {
    std::vector<std::vector<MotionForecast>> forecasts = ForwardingPredictor::forecast(graphs);
    for (auto& of_graph : forecasts) {
      for (MotionForecast& forecast : of_graph) forecast.velocity.z() *= -2.0;
    }
    return forecasts;
  }
};

// The filter asks for each graph a second time, tilted, with the history's velocity error (and only
// then), and its predictions' covariances carry the response it measured: a predictor that brings the
// heights back gives other vertical variances than constant velocity and the same horizontal ones.
std::vector<SceneFilter::Result> filter_two_objects(const MotionPredictor& predictor, bool velocity_error,
                                                    std::size_t& requests) {
  FilterOptions options;
  options.lag_window = 0.0;
  options.history_velocity_error = velocity_error;
  SceneFilter filter(predictor, options);
  std::vector<SceneFilter::Result> results;
  std::vector<Measurement> rows;
  rows.reserve(12);
  for (int k = 0; k < 6; ++k) {
    for (const double x : {0.0, 5.0}) {
      rows.push_back(Measurement{"s", 0.1 * k, "v0", x == 0.0 ? "a" : "b",
                                 Gaussian3::from_covariance(Vector3d(x + 0.1 * k, 0.0, 0.01 * (k % 2)),
                                                            0.01 * Matrix3d::Identity()),
                                 std::nullopt, std::nullopt});
    }
    const std::vector<const Measurement*> pointers{&rows[2 * k], &rows[2 * k + 1]};
    const std::vector<std::size_t> ids{2u * k, 2u * k + 1};
    filter.receive(pointers, ids);
    while (!filter.advance()) {
      const std::vector<MotionGraph>& request = filter.forecast_request();
      ++requests;
      EXPECT_EQ(request.size(), velocity_error ? 2u : 1u);
      if (velocity_error && request.size() == 2) {
        EXPECT_EQ(request[1].objects.size(), request[0].objects.size());
        for (std::size_t i = 0; i < request[0].objects.size(); ++i) {
          const ObjectHistory& history = request[0].objects[i];
          EXPECT_EQ(request[1].objects[i].positions.back(), history.positions.back());
          if (history.positions.size() >= 2) {
            EXPECT_NE(request[1].objects[i].positions.front(), history.positions.front());
          }
        }
      }
      filter.provide_forecasts(predictor.forecast(request));
    }
    std::vector<SceneFilter::Result> taken;
    filter.take_results(taken);
    results.insert(results.end(), taken.begin(), taken.end());
  }
  return results;
}

TEST(SlopeResponse, TheFilterAsksForEachGraphTiltedAndItsPredictionsCarryTheResponse) {
  const BringsHeightsBack brings_back;
  const testing::ForwardingPredictor carries_on(0.01, 1.0, 10.0, 0.09);
  std::size_t requests = 0;
  const auto back = filter_two_objects(brings_back, true, requests);
  EXPECT_GE(requests, 4u);
  const auto on = filter_two_objects(carries_on, true, requests);
  requests = 0;
  filter_two_objects(brings_back, false, requests);
  EXPECT_GE(requests, 4u);
  ASSERT_EQ(back.size(), 12u);
  ASSERT_EQ(on.size(), 12u);
  const SceneFilter::Result& last_back = back.back();
  const SceneFilter::Result& last_on = on.back();
  ASSERT_TRUE(last_back.prediction && last_on.prediction);
  const Matrix3d a = last_back.prediction->prior.covariance(), b = last_on.prediction->prior.covariance();
  EXPECT_LT((a.topLeftCorner<2, 2>() - b.topLeftCorner<2, 2>()).norm(), 1e-12);
  EXPECT_GT(std::abs(a(2, 2) - b(2, 2)), 1e-6);
}

}  // namespace
}  // namespace stgf
