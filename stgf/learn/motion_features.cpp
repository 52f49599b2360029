// SPDX-License-Identifier: Apache-2.0
#include "stgf/learn/motion_features.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "stgf/learn/motion_model.hpp"

namespace stgf {
namespace {

// Edges (j → i) of one graph of n objects starting at `first`: all pairs when small, else the k
// nearest neighbours of each object; always the self-loop.
void add_edges(const std::vector<Vector3d>& positions, std::size_t first, std::size_t n, const MotionModelShape& shape,
               std::vector<std::int64_t>& source, std::vector<std::int64_t>& target) {
  const auto full = static_cast<std::size_t>(shape.max_fully_connected);
  const auto k = static_cast<std::size_t>(shape.nearest_neighbours);
  std::vector<std::pair<double, std::size_t>> distances;
  for (std::size_t i = 0; i < n; ++i) {
    if (n <= full) {
      for (std::size_t j = 0; j < n; ++j) {
        source.push_back(static_cast<std::int64_t>(first + j));
        target.push_back(static_cast<std::int64_t>(first + i));
      }
      continue;
    }
    distances.clear();
    for (std::size_t j = 0; j < n; ++j) {
      if (j != i) distances.emplace_back((positions[first + j] - positions[first + i]).squaredNorm(), j);
    }
    const std::size_t count = std::min(k, distances.size());
    std::partial_sort(distances.begin(), distances.begin() + static_cast<std::ptrdiff_t>(count), distances.end());
    source.push_back(static_cast<std::int64_t>(first + i));
    target.push_back(static_cast<std::int64_t>(first + i));
    for (std::size_t m = 0; m < count; ++m) {
      source.push_back(static_cast<std::int64_t>(first + distances[m].second));
      target.push_back(static_cast<std::int64_t>(first + i));
    }
  }
}

}  // namespace

MotionFeatures make_motion_features(std::span<const MotionGraph> graphs, const MotionModelShape& shape,
                                    const MotionNormalisation& normalisation) {
  const int history = shape.history_length;
  MotionFeatures features;
  features.history = history;
  features.graph_offsets.push_back(0);
  for (const MotionGraph& graph : graphs) {
    for (const ObjectHistory& object : graph.objects) {
      const std::size_t points = object.positions.size();
      if (points == 0 || object.times.size() != points) {
        throw std::invalid_argument("motion graph: object '" + object.object + "' has no or inconsistent history");
      }
      const double last_time = object.times.back();
      const double dt = graph.target_time - last_time;
      if (!(dt > 0.0)) {
        throw std::invalid_argument("motion graph: object '" + object.object +
                                    "' has history at or after the target time");
      }
      // Intervals k = points−1 … 1, newest last; pad the front. Per interval: the velocity over it
      // and the acceleration from the previous interval's velocity, both per second.
      const int intervals = static_cast<int>(points) - 1;
      const int used = std::min(intervals, history);
      for (int slot = 0; slot < history - used; ++slot) {
        features.motion.insert(features.motion.end(), kMotionFeatures, 0.0f);
      }
      const auto velocity_of = [&](int k) {
        return Vector3d((object.positions[k] - object.positions[k - 1]) / (object.times[k] - object.times[k - 1]));
      };
      Vector3d velocity = Vector3d::Zero();
      double last_interval = 0.0;
      for (int k = intervals - used + 1; k <= intervals; ++k) {
        last_interval = object.times[k] - object.times[k - 1];
        if (!(last_interval > 0.0)) throw std::invalid_argument("motion graph: history times must increase");
        velocity = velocity_of(k);
        Vector3d acceleration = Vector3d::Zero();
        if (k >= 2) {
          acceleration = (velocity - velocity_of(k - 1)) / (0.5 * (object.times[k] - object.times[k - 2]));
        }
        for (int axis = 0; axis < 3; ++axis) {
          features.motion.push_back(static_cast<float>(velocity(axis) / normalisation.speed));
        }
        for (int axis = 0; axis < 3; ++axis) {
          features.motion.push_back(static_cast<float>(acceleration(axis) * normalisation.period / normalisation.speed));
        }
        features.motion.push_back(1.0f);
      }
      if (intervals == 0) velocity.setZero();
      features.last_velocities.push_back(velocity);
      features.last_intervals.push_back(intervals == 0 ? 0.0 : last_interval);
      for (int axis = 0; axis < 3; ++axis) {
        features.last_velocity.push_back(static_cast<float>(velocity(axis) / normalisation.speed));
      }
      features.horizon.push_back(static_cast<float>(dt / normalisation.period));
      features.last_interval.push_back(static_cast<float>(last_interval / normalisation.period));
      features.last_positions.push_back(object.positions.back());
      features.horizons.push_back(dt);
    }
    features.graph_offsets.push_back(features.last_positions.size());
  }
  for (std::size_t g = 0; g + 1 < features.graph_offsets.size(); ++g) {
    add_edges(features.last_positions, features.graph_offsets[g],
              features.graph_offsets[g + 1] - features.graph_offsets[g], shape, features.edge_source,
              features.edge_target);
  }
  features.edge_offset.reserve(features.edges() * 3);
  for (std::size_t e = 0; e < features.edges(); ++e) {
    const Vector3d d = (features.last_positions[static_cast<std::size_t>(features.edge_source[e])] -
                        features.last_positions[static_cast<std::size_t>(features.edge_target[e])]) /
                       normalisation.length;
    for (int axis = 0; axis < 3; ++axis) features.edge_offset.push_back(static_cast<float>(d(axis)));
  }
  return features;
}

}  // namespace stgf
