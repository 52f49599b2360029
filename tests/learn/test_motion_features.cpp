// SPDX-License-Identifier: Apache-2.0
// Φ's inputs (motion_features.hpp): the k-nearest-neighbour edges of large graphs, found through a
// grid, are exactly those (and in the order) that comparing every pair gives — for spread, clustered,
// collinear and coincident objects — and every edge list is grouped by target.

#include "stgf/model/motion_features.hpp"

#include <algorithm>
#include <random>

#include <gtest/gtest.h>

#include "stgf/learn/motion_model.hpp"

namespace stgf {
namespace {

MotionGraph graph_at(const std::vector<Vector3d>& positions) {
  MotionGraph graph{"s", "", 1.0, {}};
  for (std::size_t i = 0; i < positions.size(); ++i) {
    graph.objects.push_back(ObjectHistory{"o" + std::to_string(i), {positions[i]}, {0.0}});
  }
  return graph;
}

// Every pair compared: the self-loop, then the k nearest by (squared distance, index).
std::vector<std::pair<std::int64_t, std::int64_t>> brute_force_edges(const std::vector<Vector3d>& positions,
                                                                     std::size_t k) {
  std::vector<std::pair<std::int64_t, std::int64_t>> edges;  // (source, target)
  for (std::size_t i = 0; i < positions.size(); ++i) {
    std::vector<std::pair<double, std::size_t>> all;
    for (std::size_t j = 0; j < positions.size(); ++j) {
      if (j != i) all.emplace_back((positions[j] - positions[i]).squaredNorm(), j);
    }
    std::sort(all.begin(), all.end());
    edges.emplace_back(i, i);
    for (std::size_t m = 0; m < std::min(k, all.size()); ++m) edges.emplace_back(all[m].second, i);
  }
  return edges;
}

void expect_brute_force_edges(const std::vector<Vector3d>& positions, int k) {
  MotionModelShape shape;
  shape.max_fully_connected = 4;
  shape.nearest_neighbours = k;
  const MotionGraph graph = graph_at(positions);
  const MotionFeatures features = make_motion_features(std::span(&graph, 1), shape, MotionNormalisation{});
  std::vector<std::pair<std::int64_t, std::int64_t>> edges;
  for (std::size_t e = 0; e < features.edges(); ++e) edges.emplace_back(features.edge_source[e], features.edge_target[e]);
  EXPECT_EQ(edges, brute_force_edges(positions, static_cast<std::size_t>(k)));
}

TEST(MotionFeatures, NearestNeighboursAreThoseOfEveryPairCompared) {
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const int n : {5, 17, 60, 400}) {
    for (const int k : {1, 3, 8}) {
      std::vector<Vector3d> spread, clustered, line, grid_points;
      for (int i = 0; i < n; ++i) {
        spread.emplace_back(200.0 * uniform(random), 50.0 * uniform(random), uniform(random));
        // Most objects in one tight cluster, a few far away: the grid's cells are sized by the outliers.
        clustered.emplace_back(i % 10 == 0 ? Vector3d(1e4 * uniform(random), 1e4 * uniform(random), 0.0)
                                           : Vector3d(uniform(random), uniform(random), 0.0));
        line.emplace_back(3.0 * i, 0.0, 0.0);                         // zero area, equal gaps: ties
        grid_points.emplace_back(i % 7, (i / 7) % 5, 0.0);            // coincident objects: ties at zero
      }
      SCOPED_TRACE("n = " + std::to_string(n) + ", k = " + std::to_string(k));
      expect_brute_force_edges(spread, k);
      expect_brute_force_edges(clustered, k);
      expect_brute_force_edges(line, k);
      expect_brute_force_edges(grid_points, k);
    }
  }
}

TEST(MotionFeatures, EveryObjectAtOneSpot) {
  expect_brute_force_edges(std::vector<Vector3d>(30, Vector3d(5.0, -2.0, 1.0)), 8);
}

}  // namespace
}  // namespace stgf
