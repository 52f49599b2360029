// SPDX-License-Identifier: Apache-2.0
#include "stgf/learn/learned_methods.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>


namespace stgf {
namespace {

constexpr std::size_t kGraphsPerForwardPass = 4096;

}  // namespace

std::vector<Gaussian3> run_single_view_prediction(const MotionModel& model, std::span<const Measurement> measurements,
                                                  std::size_t* restarted_tracks) {
  const HistorySource source = HistorySource::kRawView;
  const MotionGraphSet set = make_motion_graph_set(measurements, source, model.shape().history_length + 1,  // positions = intervals + 1
                                                   model.prediction_horizon());
  if (restarted_tracks != nullptr) *restarted_tracks = set.restarted_tracks;

  std::vector<std::vector<Vector3d>> predictions;
  predictions.reserve(set.graphs.size());
  for (std::size_t first = 0; first < set.graphs.size(); first += kGraphsPerForwardPass) {
    const std::size_t count = std::min(kGraphsPerForwardPass, set.graphs.size() - first);
    for (auto& graph : model.predict(std::span(set.graphs).subspan(first, count))) predictions.push_back(std::move(graph));
  }

  const double speed = model.normalisation().speed;
  std::vector<Gaussian3> estimates;
  estimates.reserve(measurements.size());
  for (std::size_t row = 0; row < measurements.size(); ++row) {
    const auto& index = set.predictor_of_row[row];
    if (!index) {  // a first sighting: its own measurement
      estimates.push_back(measurements[row].position);
      continue;
    }
    const MotionGraph& graph = set.graphs[index->graph];
    const ObjectHistory& history = graph.objects[index->object];
    const double dt = graph.target_time - history.times.back();
    Matrix3d covariance = set.latest_covariances[index->graph][index->object] + model.process_noise(dt);
    if (history.positions.size() == 1) covariance += (speed * dt) * (speed * dt) * Matrix3d::Identity();
    estimates.push_back(Gaussian3::from_covariance(predictions[index->graph][index->object], covariance));
  }
  return estimates;
}

}  // namespace stgf
