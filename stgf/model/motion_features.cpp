// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/motion_features.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <utility>

#include "stgf/model/trained_motion_model.hpp"

namespace stgf {
namespace {

// The k nearest of each of the n objects at positions[first …], as (squared distance, index within
// the graph) sorted by distance, then index: the order comparing every pair gives. A uniform grid
// over x–y with about k objects per cell is searched in growing square rings of cells around each
// object until no cell left can hold anything as close as the k-th found (3-D distances are at least
// the x–y ones), so a graph costs O(n k) for evenly spread objects, not O(n²).
class NearestNeighbours {
 public:
  NearestNeighbours(const std::vector<Vector3d>& positions, std::size_t first, std::size_t n, std::size_t k)
      : positions_(positions), first_(first), k_(std::min(k, n - 1)) {
    Eigen::Vector2d low = positions[first].head<2>(), high = low;
    for (std::size_t i = 0; i < n; ++i) {
      low = low.cwiseMin(positions[first + i].head<2>());
      high = high.cwiseMax(positions[first + i].head<2>());
    }
    low_ = low;
    const Eigen::Vector2d extent = high - low;
    // About k objects per cell over the occupied area, and at most 4n cells along either side (a
    // thin strip of objects has almost no area).
    const double per_cell = static_cast<double>(std::max<std::size_t>(k_, 1));
    cell_ = std::max(std::sqrt(extent.x() * extent.y() * per_cell / static_cast<double>(n)),
                     extent.maxCoeff() / (4.0 * static_cast<double>(n)));
    if (!(cell_ > 0.0) || !std::isfinite(cell_)) cell_ = 1.0;  // every object at one spot: one cell
    columns_ = cell_of(high.x() - low.x()) + 1;
    rows_ = cell_of(high.y() - low.y()) + 1;
    start_.assign(static_cast<std::size_t>(columns_ * rows_) + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start_[index_of(i) + 1];
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    members_.resize(n);
    std::vector<std::size_t> next(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) members_[next[index_of(i)]++] = i;  // ascending within a cell
  }

  // Object i's k nearest (never itself).
  const std::vector<std::pair<double, std::size_t>>& of(std::size_t i) {
    found_.clear();
    const Vector3d& p = positions_[first_ + i];
    const long column = cell_of(p.x() - low_.x());
    const long row = cell_of(p.y() - low_.y());
    for (long ring = 0;; ++ring) {
      for (long r = row - ring; r <= row + ring; ++r) {
        for (long c = column - ring; c <= column + ring; ++c) {
          if (std::max(std::abs(r - row), std::abs(c - column)) != ring) continue;  // the ring's border only
          if (r < 0 || r >= rows_ || c < 0 || c >= columns_) continue;
          const auto cell = static_cast<std::size_t>(r * columns_ + c);
          for (std::size_t m = start_[cell]; m < start_[cell + 1]; ++m) {
            const std::size_t j = members_[m];
            if (j != i) found_.emplace_back((positions_[first_ + j] - p).squaredNorm(), j);
          }
        }
      }
      const bool everything_seen = ring > std::max({row, column, rows_ - 1 - row, columns_ - 1 - column});
      if (found_.size() >= k_) {
        std::partial_sort(found_.begin(), found_.begin() + static_cast<std::ptrdiff_t>(k_), found_.end());
        // Cells beyond this ring lie at least ring × cell away in x or y.
        const double beyond = static_cast<double>(ring) * cell_;
        if (everything_seen || k_ == 0 || found_[k_ - 1].first < beyond * beyond) break;
      } else if (everything_seen) {
        break;
      }
    }
    found_.resize(std::min(found_.size(), k_));
    return found_;
  }

 private:
  long cell_of(double offset) const { return static_cast<long>(std::floor(offset / cell_)); }
  std::size_t index_of(std::size_t i) const {
    const Vector3d& p = positions_[first_ + i];
    return static_cast<std::size_t>(cell_of(p.y() - low_.y()) * columns_ + cell_of(p.x() - low_.x()));
  }

  const std::vector<Vector3d>& positions_;
  std::size_t first_, k_;
  Eigen::Vector2d low_;
  double cell_ = 1.0;
  long columns_ = 1, rows_ = 1;
  std::vector<std::size_t> start_;    // per cell, into members_
  std::vector<std::size_t> members_;  // objects by cell
  std::vector<std::pair<double, std::size_t>> found_;
};

// Edges (j → i) of one graph of n objects starting at `first`: all pairs when small, else the k
// nearest neighbours of each object; always the self-loop. Grouped by target i, ascending.
void add_edges(const std::vector<Vector3d>& positions, std::size_t first, std::size_t n, const MotionModelShape& shape,
               std::vector<std::int64_t>& source, std::vector<std::int64_t>& target) {
  if (n <= static_cast<std::size_t>(shape.max_fully_connected)) {
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = 0; j < n; ++j) {
        source.push_back(static_cast<std::int64_t>(first + j));
        target.push_back(static_cast<std::int64_t>(first + i));
      }
    }
    return;
  }
  NearestNeighbours nearest(positions, first, n, static_cast<std::size_t>(shape.nearest_neighbours));
  for (std::size_t i = 0; i < n; ++i) {
    source.push_back(static_cast<std::int64_t>(first + i));
    target.push_back(static_cast<std::int64_t>(first + i));
    for (const auto& [distance, j] : nearest.of(i)) {
      source.push_back(static_cast<std::int64_t>(first + j));
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
