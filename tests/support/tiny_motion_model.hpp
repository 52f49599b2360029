// SPDX-License-Identifier: Apache-2.0
#pragma once
// A motion model shape small enough that an untrained Φ runs in microseconds in tests.

#include "stgf/learn/motion_model.hpp"

namespace stgf::testing {

inline MotionModelShape tiny_shape() {
  MotionModelShape shape;
  shape.history_length = 4;
  shape.embedding = 8;
  shape.hidden = 8;
  shape.attention_hidden = 4;
  shape.max_fully_connected = 4;
  shape.nearest_neighbours = 2;
  return shape;
}

}  // namespace stgf::testing
