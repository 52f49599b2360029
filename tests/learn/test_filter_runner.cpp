// SPDX-License-Identifier: Apache-2.0
// Running `ours` over many scenes at once (methods/filter_runner.hpp) gives what running each scene's
// filter on its own gives, bitwise, with a constant-velocity predictor and with Φ (whose forward pass
// computes each object from its own graph, whatever else is in the batch).

#include "stgf/methods/filter_runner.hpp"
#include "stgf/methods/spatiotemporal_graph_filter.hpp"

#include <cmath>
#include <set>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "stgf/datasets/synthetic.hpp"
#include "stgf/learn/motion_model.hpp"
#include "stgf/methods/run_method.hpp"
#include "support/test_predictors.hpp"

namespace stgf {
namespace {

std::vector<Measurement> synthetic_scenes() {
  SyntheticOptions options;
  options.seed = 5;
  options.scenes = 6;
  options.objects = 5;
  options.views = 3;
  options.steps = 25;
  return make_synthetic_benchmark(options).test.measurements;
}

std::vector<Gaussian3> scene_by_scene(const MotionPredictor& predictor, const SpatiotemporalGraphFilter::Options& options,
                                      std::span<const Measurement> rows) {
  return run_localizer([&] { return std::make_unique<SpatiotemporalGraphFilter>(predictor, options); }, rows);
}

void expect_close(const std::vector<Gaussian3>& a, const std::vector<Gaussian3>& b, double tolerance) {
  ASSERT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    worst = std::max(worst, (a[k].mean() - b[k].mean()).norm());
    worst = std::max(worst, (a[k].covariance() - b[k].covariance()).norm());
  }
  EXPECT_LE(worst, tolerance);
}

TEST(FilterRunner, MatchesSceneBySceneWithAConstantVelocityPredictor) {
  const std::vector<Measurement> rows = synthetic_scenes();
  const ConstantVelocityPredictor predictor(0.5, 1.2, /*horizon=*/0.35);
  const SpatiotemporalGraphFilter::Options options{RegistrationPrior{Vector3d(0.1, 0.1, 0.0), Vector3d::Constant(0.3)}, true};
  const FilterRun run = run_spatiotemporal_graph_filter(predictor, options, rows, /*keep_predictions=*/true);
  expect_close(run.estimates, scene_by_scene(predictor, options, rows), 0.0);
  ASSERT_EQ(run.predictions.size(), rows.size());
  EXPECT_GT(std::count_if(run.predictions.begin(), run.predictions.end(), [](const auto& p) { return p.has_value(); }),
            static_cast<std::ptrdiff_t>(rows.size() / 2));
}

TEST(FilterRunner, MatchesSceneBySceneWithTheLearnedModel) {
  const std::vector<Measurement> rows = synthetic_scenes();
  MotionModelShape shape;
  shape.history_length = 4;
  const MotionModel model(shape, MotionNormalisation{1.2, 0.1, 5.0, 0.1}, 7);
  const SpatiotemporalGraphFilter::Options options{RegistrationPrior{Vector3d(0.1, 0.1, 0.0), Vector3d::Constant(0.3)}, true};
  const FilterRun run = run_spatiotemporal_graph_filter(model, options, rows);
  expect_close(run.estimates, scene_by_scene(model, options, rows), 0.0);
  // Deterministic.
  expect_close(run.estimates, run_spatiotemporal_graph_filter(model, options, rows).estimates, 0.0);
}

// Steps 0.1 s apart, none from 0.5 to 1.0 s: after the gap, longer than the predictor's horizon, every
// track seen before it starts again, with no prediction.
TEST(FilterRunner, CountsRestartedTracksOverScenes) {
  std::vector<Measurement> rows;
  for (const Measurement& row : synthetic_scenes()) {
    if (row.time < 0.45 || row.time > 1.05) rows.push_back(row);
  }
  const ConstantVelocityPredictor predictor(0.5, 1.2, /*horizon=*/0.05);  // shorter than a step
  const FilterRun run = run_spatiotemporal_graph_filter(predictor, {}, rows, true);
  std::set<std::pair<std::string, std::string>> before, after;  // (scene, object) seen at 0.4 s, at 1.1 s
  std::size_t first_after = 0, predicted_first_after = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (std::abs(rows[k].time - 0.4) < 1e-9) before.emplace(rows[k].scene, rows[k].object);
    if (std::abs(rows[k].time - 1.1) < 1e-9) {
      after.emplace(rows[k].scene, rows[k].object);
      ++first_after;
      if (run.predictions[k]) ++predicted_first_after;
    }
  }
  std::size_t restarted = 0;
  for (const auto& key : after) restarted += before.count(key);
  ASSERT_GT(restarted, 0u);
  EXPECT_GE(run.restarted_tracks, restarted);
  EXPECT_GT(first_after, 0u);
  EXPECT_EQ(predicted_first_after, 0u);
}

// With a predictor that coasts, a track crosses one missed frame (0.2 s unseen at 10 frames/s) even
// beyond the coasting horizon: it starts again only past 2.5 frame intervals, its own or, before it
// has one, the scene's (ObjectTrack::unseen_limit). A predictor that does not coast restarts them.
TEST(FilterRunner, ACoastingTrackCrossesOneMissedFrameAtTheScenesRate) {
  std::vector<Measurement> rows;
  for (const Measurement& row : synthetic_scenes()) {
    if (std::abs(row.time - 0.1) > 1e-9 && std::abs(row.time - 0.5) > 1e-9) rows.push_back(row);
  }
  const testing::CoastingPredictor coasting(/*horizon=*/0.05, /*coasting_horizon=*/0.08);
  EXPECT_EQ(run_spatiotemporal_graph_filter(coasting, {}, rows).restarted_tracks, 0u);
  const ConstantVelocityPredictor plain(0.5, 1.2, /*horizon=*/0.08);
  EXPECT_GT(run_spatiotemporal_graph_filter(plain, {}, rows).restarted_tracks, 0u);
}

}  // namespace
}  // namespace stgf
