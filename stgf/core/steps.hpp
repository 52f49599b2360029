// SPDX-License-Identifier: Apache-2.0
#pragma once
// Groups measurements into scenes and steps: rows with the same scene and a time within
// kSameStepTolerance of the step's first (earliest) time form one step. Scenes keep the order in
// which they first appear; steps within a scene are in increasing time.

#include <span>
#include <string>
#include <vector>

#include "stgf/core/records.hpp"

namespace stgf {

struct Step {
  double time = 0.0;                 // the earliest time of the step's rows
  std::vector<std::size_t> rows;     // indices into the measurement list, in list order
};

struct Scene {
  std::string name;
  std::vector<Step> steps;
};

std::vector<Scene> group_into_scenes(std::span<const Measurement> measurements);

// The rows of every `stride`-th step of each scene (steps 0, stride, 2·stride, …), in their order:
// the same scenes seen at 1/stride of the frame rate. stride 1 keeps every row. Throws
// std::invalid_argument for stride < 1.
std::vector<Measurement> every_nth_step(std::span<const Measurement> measurements, int stride);

}  // namespace stgf
