// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/motion_predictor.hpp"

namespace stgf {

std::vector<std::vector<Vector3d>> MotionPredictor::predict(std::span<const MotionGraph> graphs) const {
  const std::vector<std::vector<MotionForecast>> forecasts = forecast(graphs);
  std::vector<std::vector<Vector3d>> predictions(graphs.size());
  for (std::size_t g = 0; g < graphs.size(); ++g) {
    for (std::size_t i = 0; i < graphs[g].objects.size(); ++i) {
      const ObjectHistory& history = graphs[g].objects[i];
      predictions[g].push_back(history.positions.back() +
                               forecasts[g][i].displacement(graphs[g].target_time - history.times.back()));
    }
  }
  return predictions;
}

std::vector<std::vector<MotionForecast>> ConstantVelocityPredictor::forecast(std::span<const MotionGraph> graphs) const {
  std::vector<std::vector<MotionForecast>> forecasts;
  forecasts.reserve(graphs.size());
  for (const MotionGraph& graph : graphs) {
    std::vector<MotionForecast>& of_graph = forecasts.emplace_back();
    for (const ObjectHistory& history : graph.objects) {
      const std::size_t n = history.positions.size();
      MotionForecast forecast;
      if (n >= 2) {
        forecast.velocity =
            (history.positions[n - 1] - history.positions[n - 2]) / (history.times[n - 1] - history.times[n - 2]);
      }
      of_graph.push_back(forecast);
    }
  }
  return forecasts;
}

}  // namespace stgf
