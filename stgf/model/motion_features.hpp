// SPDX-License-Identifier: Apache-2.0
#pragma once
// Φ's inputs for a batch of graphs (motion_model.hpp gives the math), in single precision as the
// network reads them, and what turns its output back into metres, in double precision. Both forms
// of the network read these same numbers: LibTorch's for training (motion_network.hpp) and the Eigen
// forward pass for inference (motion_inference.hpp). No LibTorch here.
//
// Positions never enter the network as absolute values: only differences, computed in double before
// conversion, so world coordinates of any size work.

#include <cstdint>
#include <span>
#include <vector>

#include "stgf/core/motion_graph.hpp"

namespace stgf {

struct MotionModelShape;
struct MotionNormalisation;

inline constexpr int kMotionFeatures = 7;  // per history interval: v / s_v (3), a s_t / s_v (3), valid

struct MotionFeatures {
  int history = 0;                   // H
  std::vector<float> motion;         // [N][H][7], oldest interval first, short histories padded at the start
  std::vector<float> last_velocity;  // [N][3]: v_last / s_v (zero without a velocity)
  std::vector<float> horizon;        // [N]: Δt / s_t
  std::vector<float> last_interval;  // [N]: Δt_last / s_t (zero without a velocity)
  // Edges j → i (object i attends to j), grouped by target: every edge into i is contiguous, i ascending.
  std::vector<std::int64_t> edge_source;
  std::vector<std::int64_t> edge_target;
  std::vector<float> edge_offset;    // [E][3]: (p_j − p_i) / s_p
  // Per object, in double, to turn the predicted acceleration into a forecast.
  std::vector<Vector3d> last_positions;
  std::vector<double> horizons;             // Δt (s)
  std::vector<Vector3d> last_velocities;    // v_last (m/s), zero without a velocity
  std::vector<double> last_intervals;       // Δt_last (s), zero without a velocity
  std::vector<std::size_t> graph_offsets;   // first object of each graph; size = graphs + 1

  std::size_t objects() const { return last_positions.size(); }
  std::size_t edges() const { return edge_source.size(); }
};

// Throws std::invalid_argument for an object without history, with inconsistent or non-increasing
// times, or with history at or after its graph's target time.
MotionFeatures make_motion_features(std::span<const MotionGraph> graphs, const MotionModelShape& shape,
                                    const MotionNormalisation& normalisation);

}  // namespace stgf
