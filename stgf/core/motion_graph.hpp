// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a motion model (the learned Φ, or constant velocity) sees (DESIGN §1.1): at one step, the graph of
// objects one view holds, each with its recent positions, to be predicted at a target time.
//
// Histories hold positions and their times, oldest first; the last entry is the latest known
// position. Φ works on motion — velocities (z_k − z_{k−1}) / (t_k − t_{k−1}) in m/s and the step
// periods — so it does not care where the scene is or at which rate it was sampled.

#include <string>
#include <vector>

#include "stgf/core/gaussian.hpp"

namespace stgf {

struct ObjectHistory {
  std::string object;
  std::vector<Vector3d> positions;  // oldest first; at least one
  std::vector<double> times;        // seconds, strictly increasing, same length as positions
};

struct MotionGraph {
  std::string scene;
  std::string view;          // empty when the graph is shared by all views (fused histories)
  double target_time = 0.0;  // when the prediction is for (after every history time)
  std::vector<ObjectHistory> objects;
};


}  // namespace stgf
