// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/learned_methods.hpp"

#include <algorithm>
#include <iterator>

namespace stgf {

std::vector<Gaussian3> run_single_view_prediction(const TrainedMotionModel& model, std::span<const Measurement> measurements,
                                                  std::size_t* restarted_tracks) {
  SingleViewPredictionStream stream(model);
  std::vector<Gaussian3> estimates = stream.add(measurements);
  std::vector<Gaussian3> rest = stream.finish();
  estimates.insert(estimates.end(), std::make_move_iterator(rest.begin()), std::make_move_iterator(rest.end()));
  if (restarted_tracks != nullptr) *restarted_tracks = stream.restarted_tracks();
  return estimates;
}

SingleViewPredictionStream::SingleViewPredictionStream(const TrainedMotionModel& model) : model_(model) {}

std::vector<Gaussian3> SingleViewPredictionStream::add(std::span<const Measurement> rows) {
  Part part;
  part.set = make_motion_graph_set(rows, HistorySource::kRawView, model_.shape().history_length + 1,  // positions = intervals + 1
                                   model_.prediction_horizon());
  for (std::size_t row = 0; row < rows.size(); ++row) {
    if (!part.set.predictor_of_row[row]) part.first_sightings.push_back(rows[row].position);
  }
  part.predictions.reserve(part.set.graphs.size());
  restarted_tracks_ += part.set.restarted_tracks;
  waiting_ += part.set.graphs.size();
  parts_.push_back(std::move(part));
  run_passes(/*to_the_end=*/false);
  std::vector<Gaussian3> estimates;
  take_complete(estimates);
  return estimates;
}

std::vector<Gaussian3> SingleViewPredictionStream::finish() {
  run_passes(/*to_the_end=*/true);
  std::vector<Gaussian3> estimates;
  take_complete(estimates);
  return estimates;
}

void SingleViewPredictionStream::run_passes(bool to_the_end) {
  while (waiting_ >= kGraphsPerForwardPass || (to_the_end && waiting_ > 0)) {
    const std::size_t count = std::min(kGraphsPerForwardPass, waiting_);
    // The pass's graphs: the first `count` not predicted, in order. They lie in one part unless the
    // pass crosses a part's end; then they are copied together.
    auto first = std::find_if(parts_.begin(), parts_.end(),
                              [](const Part& part) { return part.predictions.size() < part.set.graphs.size(); });
    const std::span<const MotionGraph> in_first = std::span(first->set.graphs).subspan(first->predictions.size());
    std::vector<MotionGraph> crossing;
    if (in_first.size() < count) {
      for (auto part = first; crossing.size() < count; ++part) {
        const auto& graphs = part->set.graphs;
        const std::size_t from = part->predictions.size();
        const std::size_t take = std::min(count - crossing.size(), graphs.size() - from);
        crossing.insert(crossing.end(), graphs.begin() + static_cast<std::ptrdiff_t>(from),
                        graphs.begin() + static_cast<std::ptrdiff_t>(from + take));
      }
    }
    std::vector<std::vector<Vector3d>> predicted =
        model_.predict(crossing.empty() ? in_first.first(count) : std::span<const MotionGraph>(crossing));
    auto part = first;
    for (std::vector<Vector3d>& graph : predicted) {
      while (part->predictions.size() == part->set.graphs.size()) ++part;
      part->predictions.push_back(std::move(graph));
    }
    waiting_ -= count;
  }
}

void SingleViewPredictionStream::take_complete(std::vector<Gaussian3>& estimates) {
  const double speed = model_.normalisation().speed;
  while (!parts_.empty() && parts_.front().predictions.size() == parts_.front().set.graphs.size()) {
    const Part& part = parts_.front();
    std::size_t next_first_sighting = 0;
    for (const auto& index : part.set.predictor_of_row) {
      if (!index) {  // a first sighting: its own measurement
        estimates.push_back(part.first_sightings[next_first_sighting++]);
        continue;
      }
      const MotionGraph& graph = part.set.graphs[index->graph];
      const ObjectHistory& history = graph.objects[index->object];
      const double dt = graph.target_time - history.times.back();
      Matrix3d covariance = part.set.latest_covariances[index->graph][index->object] + model_.process_noise(dt);
      if (history.positions.size() == 1) covariance += (speed * dt) * (speed * dt) * Matrix3d::Identity();
      estimates.push_back(Gaussian3::from_covariance(part.predictions[index->graph][index->object], covariance));
    }
    parts_.pop_front();
  }
}

}  // namespace stgf
