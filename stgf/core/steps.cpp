// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/steps.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace stgf {

std::vector<Scene> group_into_scenes(std::span<const Measurement> measurements) {
  std::vector<Scene> scenes;
  std::vector<std::vector<std::size_t>> rows_of_scene;
  std::unordered_map<std::string, std::size_t> scene_index;
  for (std::size_t row = 0; row < measurements.size(); ++row) {
    const auto [it, inserted] = scene_index.try_emplace(measurements[row].scene, scenes.size());
    if (inserted) {
      scenes.push_back(Scene{measurements[row].scene, {}});
      rows_of_scene.emplace_back();
    }
    rows_of_scene[it->second].push_back(row);
  }
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    std::vector<std::size_t>& rows = rows_of_scene[s];
    std::stable_sort(rows.begin(), rows.end(), [&](std::size_t a, std::size_t b) {
      return measurements[a].time < measurements[b].time;
    });
    std::vector<Step>& steps = scenes[s].steps;
    for (std::size_t row : rows) {
      const double time = measurements[row].time;
      if (steps.empty() || time - steps.back().time > kSameStepTolerance) {
        steps.push_back(Step{time, {}});
      }
      steps.back().rows.push_back(row);
    }
    for (Step& step : steps) std::sort(step.rows.begin(), step.rows.end());
  }
  return scenes;
}

std::vector<Measurement> every_nth_step(std::span<const Measurement> measurements, int stride) {
  if (stride < 1) throw std::invalid_argument("every_nth_step: stride must be at least 1");
  std::vector<bool> kept(measurements.size(), false);
  for (const Scene& scene : group_into_scenes(measurements)) {
    for (std::size_t step = 0; step < scene.steps.size(); step += static_cast<std::size_t>(stride)) {
      for (std::size_t row : scene.steps[step].rows) kept[row] = true;
    }
  }
  std::vector<Measurement> rows;
  for (std::size_t row = 0; row < measurements.size(); ++row) {
    if (kept[row]) rows.push_back(measurements[row]);
  }
  return rows;
}

}  // namespace stgf
