#include "stgf/learn/motion_predictor.hpp"

namespace stgf {

std::vector<std::vector<Vector3d>> ConstantVelocityPredictor::predict(std::span<const MotionGraph> graphs) const {
  std::vector<std::vector<Vector3d>> predictions;
  predictions.reserve(graphs.size());
  for (const MotionGraph& graph : graphs) {
    std::vector<Vector3d>& predicted = predictions.emplace_back();
    for (const ObjectHistory& history : graph.objects) {
      const std::size_t n = history.positions.size();
      Vector3d velocity = Vector3d::Zero();
      if (n >= 2) {
        velocity = (history.positions[n - 1] - history.positions[n - 2]) / (history.times[n - 1] - history.times[n - 2]);
      }
      predicted.push_back(history.positions.back() + velocity * (graph.target_time - history.times.back()));
    }
  }
  return predictions;
}

}  // namespace stgf
