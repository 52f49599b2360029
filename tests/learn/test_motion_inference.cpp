// SPDX-License-Identifier: Apache-2.0
// Φ's Eigen forward pass (motion_inference.hpp) against the LibTorch network it replaces for
// inference: the same accelerations to 1e-5 on random graphs and weights (fully connected and
// k-nearest graphs, short and single-position histories, the default shape and a tiny one), each
// object's forecast independent of what else is in the batch, and the model's forecast following
// the weights as training changes them.

#include "stgf/model/motion_inference.hpp"

#include <random>

#include <gtest/gtest.h>
#include <torch/torch.h>

#include "stgf/learn/motion_model.hpp"
#include "stgf/learn/motion_network.hpp"
#include "support/tiny_motion_model.hpp"

namespace stgf {
namespace {

// Random graphs: 1…`max_objects` objects each, histories of 1…history+3 positions at irregular times.
std::vector<MotionGraph> random_graphs(int count, int max_objects, int history, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<MotionGraph> graphs;
  for (int g = 0; g < count; ++g) {
    MotionGraph graph{"s" + std::to_string(g), "", 0.0, {}};
    const int objects = 1 + static_cast<int>(uniform(random) * max_objects);
    double latest = 0.0;
    for (int i = 0; i < objects; ++i) {
      ObjectHistory object{"o" + std::to_string(i), {}, {}};
      const int positions = 1 + static_cast<int>(uniform(random) * (history + 3));
      Vector3d position(1000.0 + 30.0 * uniform(random), -500.0 + 30.0 * uniform(random), uniform(random));
      const Vector3d velocity(3.0 * (uniform(random) - 0.5), 3.0 * (uniform(random) - 0.5), 0.0);
      double t = 5.0 * uniform(random);
      for (int k = 0; k < positions; ++k) {
        object.positions.push_back(position);
        object.times.push_back(t);
        const double dt = 0.05 + 0.3 * uniform(random);
        position += velocity * dt + 0.1 * Vector3d(uniform(random) - 0.5, uniform(random) - 0.5, 0.0);
        t += dt;
      }
      latest = std::max(latest, object.times.back());
      graph.objects.push_back(std::move(object));
    }
    graph.target_time = latest + 0.1;
    graphs.push_back(std::move(graph));
  }
  return graphs;
}

// Weights far from the small-head initialisation, so that every part of the network matters.
void randomise_weights(MotionModel& model, std::uint64_t seed) {
  torch::manual_seed(seed);
  torch::NoGradGuard no_grad;
  for (torch::Tensor& parameter : model.impl().network->parameters()) parameter.normal_(0.0, 0.4);
}

Eigen::Matrix3Xf torch_accelerations(MotionModel& model, std::span<const MotionGraph> graphs) {
  const detail::MotionBatch batch = detail::make_motion_batch(graphs, model.shape(), model.normalisation());
  torch::NoGradGuard no_grad;
  model.impl().network->eval();
  const torch::Tensor a = model.impl().network->acceleration(batch).contiguous();
  return Eigen::Map<const Eigen::Matrix<float, 3, Eigen::Dynamic>>(a.data_ptr<float>(), 3, a.size(0));
}

Eigen::Matrix3Xf eigen_accelerations(const MotionModel& model, std::span<const MotionGraph> graphs) {
  const MotionFeatures features = make_motion_features(graphs, model.shape(), model.normalisation());
  return model.impl().inference()->accelerations(features);
}

void expect_same_accelerations(const MotionModelShape& shape, int max_objects, std::uint64_t seed) {
  MotionModel model(shape, MotionNormalisation{1.3, 0.1, 5.0, 0.3}, seed);
  randomise_weights(model, seed);
  const std::vector<MotionGraph> graphs = random_graphs(40, max_objects, shape.history_length, seed);
  const Eigen::Matrix3Xf expected = torch_accelerations(model, graphs);
  const Eigen::Matrix3Xf actual = eigen_accelerations(model, graphs);
  ASSERT_EQ(actual.cols(), expected.cols());
  ASSERT_GT(expected.cols(), 40);
  ASSERT_GT(expected.cwiseAbs().maxCoeff(), 0.1f);  // the outputs are not all near zero
  for (Eigen::Index n = 0; n < expected.cols(); ++n) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(actual(axis, n), expected(axis, n), 1e-5f * std::max(1.0f, std::abs(expected(axis, n))))
          << "object " << n << " axis " << axis;
    }
  }
}

TEST(MotionInference, MatchesLibTorchOnFullyConnectedGraphsWithTheDefaultShape) {
  expect_same_accelerations(MotionModelShape{}, 12, 11);
}

TEST(MotionInference, MatchesLibTorchOnNearestNeighbourGraphs) {
  MotionModelShape shape = stgf::testing::tiny_shape();
  expect_same_accelerations(shape, 3 * shape.max_fully_connected, 12);
  expect_same_accelerations(MotionModelShape{}, 40, 13);  // > 16 objects: 8 nearest neighbours
}

TEST(MotionInference, AnObjectsForecastDoesNotDependOnTheRestOfTheBatch) {
  MotionModel model(MotionModelShape{}, MotionNormalisation{}, 3);
  randomise_weights(model, 3);
  const std::vector<MotionGraph> graphs = random_graphs(30, 20, 8, 5);
  const std::vector<std::vector<MotionForecast>> together = model.forecast(graphs);
  for (std::size_t g = 0; g < graphs.size(); ++g) {
    const std::vector<std::vector<MotionForecast>> alone = model.forecast(std::span(&graphs[g], 1));
    ASSERT_EQ(alone[0].size(), together[g].size());
    for (std::size_t i = 0; i < alone[0].size(); ++i) {
      // Bitwise: the same operations in the same order.
      EXPECT_EQ(alone[0][i].velocity, together[g][i].velocity) << "graph " << g << " object " << i;
      EXPECT_EQ(alone[0][i].acceleration, together[g][i].acceleration) << "graph " << g << " object " << i;
    }
  }
}

// Objects met before take their encoder state from the memo: the same bits as encoding them, in a
// batch where the others are new (the memo's copy in `fresh` starts empty).
TEST(MotionInference, AnObjectFromTheMemoGetsTheSameBitsAsEncodingIt) {
  MotionModel model(MotionModelShape{}, MotionNormalisation{}, 9);
  randomise_weights(model, 9);
  const std::vector<MotionGraph> seen = random_graphs(10, 6, 8, 21), unseen = random_graphs(10, 6, 8, 22);
  std::vector<MotionGraph> mixed = seen;
  mixed.insert(mixed.end(), unseen.begin(), unseen.end());
  const MotionFeatures features = make_motion_features(mixed, model.shape(), model.normalisation());
  const MotionInference fresh = *model.impl().inference();
  const Eigen::Matrix3Xf encoded = fresh.accelerations(features);
  const MotionInference& remembering = *model.impl().inference();
  remembering.accelerations(make_motion_features(seen, model.shape(), model.normalisation()));
  const Eigen::Matrix3Xf from_memo = remembering.accelerations(features);
  const Eigen::Matrix3Xf again = remembering.accelerations(features);
  ASSERT_EQ(encoded.cols(), from_memo.cols());
  EXPECT_TRUE((encoded.array() == from_memo.array()).all());
  EXPECT_TRUE((encoded.array() == again.array()).all());
}

TEST(MotionInference, ForecastFollowsTheWeightsAsTheyChange) {
  MotionModel model(stgf::testing::tiny_shape(), MotionNormalisation{}, 4);
  const std::vector<MotionGraph> graphs = random_graphs(3, 4, 4, 6);
  const Vector3d before = model.forecast(graphs)[0][0].acceleration;
  randomise_weights(model, 8);  // what an optimizer step does: the parameters change in place
  const Vector3d after = model.forecast(graphs)[0][0].acceleration;
  EXPECT_GT((after - before).norm(), 1e-3);
  EXPECT_NEAR((after - torch_accelerations(model, graphs).col(0).cast<double>() *
                           (model.normalisation().speed / model.normalisation().period))
                  .norm(),
              0.0, 1e-4);
}

TEST(MotionInference, RejectsWeightsThatDoNotFit) {
  MotionNetworkWeights weights;  // all empty
  EXPECT_THROW(MotionInference{weights}, std::invalid_argument);
}

}  // namespace
}  // namespace stgf
