#include "stgf/learn/spatiotemporal_graph_filter.hpp"

#include <optional>
#include <stdexcept>
#include <string_view>
#include <unordered_map>

#include "stgf/core/multi_view_update.hpp"

namespace stgf {

std::vector<Gaussian3> SpatiotemporalGraphFilter::step(double time,
                                                       std::span<const Measurement* const> measurements) {
  const std::vector<MotionGraph> graphs = prepare_step(time, measurements);
  return complete_step(predictor_.predict(graphs));
}

std::vector<MotionGraph> SpatiotemporalGraphFilter::prepare_step(double time,
                                                                 std::span<const Measurement* const> measurements) {
  if (pending_) throw std::logic_error("SpatiotemporalGraphFilter: prepare_step twice without complete_step");
  // The graph of each view: the objects it measures now and has tracked before (views in order of
  // first appearance among the rows, objects in row order).
  std::vector<MotionGraph> graphs;
  std::unordered_map<std::string_view, std::size_t> graph_of_view;
  Pending pending{time, {measurements.begin(), measurements.end()}, {}, {}};
  pending.prediction_of_row.resize(measurements.size());
  for (std::size_t row = 0; row < measurements.size(); ++row) {
    const Measurement& measurement = *measurements[row];
    const auto view = tracks_.find(measurement.view);
    if (view == tracks_.end()) continue;
    const auto track = view->second.find(measurement.object);
    if (track == view->second.end() || track->second.empty()) continue;
    if (time - track->second.back().time > predictor_.prediction_horizon()) {
      track->second.clear();  // unseen for too long: starts again, like an object never seen
      ++restarted_tracks_;
      continue;
    }
    const auto [entry, inserted] = graph_of_view.try_emplace(measurement.view, graphs.size());
    if (inserted) graphs.push_back(MotionGraph{measurement.scene, measurement.view, time, {}});
    MotionGraph& graph = graphs[entry->second];
    ObjectHistory history{measurement.object, {}, {}};
    for (const TrackPoint& point : track->second) {
      history.positions.push_back(point.estimate.mean());
      history.times.push_back(point.time);
    }
    pending.prediction_of_row[row] = std::make_pair(entry->second, graph.objects.size());
    graph.objects.push_back(std::move(history));
  }
  pending.graph_sizes.reserve(graphs.size());
  for (const MotionGraph& graph : graphs) pending.graph_sizes.push_back(graph.objects.size());
  pending_ = std::move(pending);
  return graphs;
}

std::vector<Gaussian3> SpatiotemporalGraphFilter::complete_step(const std::vector<std::vector<Vector3d>>& predicted) {
  if (!pending_) throw std::logic_error("SpatiotemporalGraphFilter: complete_step without prepare_step");
  const Pending pending = std::move(*pending_);
  pending_.reset();
  if (predicted.size() != pending.graph_sizes.size()) {
    throw std::invalid_argument("SpatiotemporalGraphFilter: complete_step needs one prediction per graph");
  }
  for (std::size_t g = 0; g < predicted.size(); ++g) {
    if (predicted[g].size() != pending.graph_sizes[g]) {
      throw std::invalid_argument("SpatiotemporalGraphFilter: complete_step needs one prediction per graph object");
    }
  }
  const double time = pending.time;
  const std::span<const Measurement* const> measurements = pending.rows;
  const auto& prediction_of_row = pending.prediction_of_row;

  // Every view's measurements of each object, shared by all views.
  std::unordered_map<std::string_view, std::vector<Gaussian3>> measurements_of_object;
  std::unordered_map<std::string_view, std::vector<const Measurement*>> rows_of_object;
  for (const Measurement* measurement : measurements) {
    measurements_of_object[measurement->object].push_back(measurement->position);
    rows_of_object[measurement->object].push_back(measurement);
  }
  // One combined measurement per object: corrected for the registration offsets when there are any
  // to account for, else the information-weighted mean (then used for the innovation and a diffuse start).
  std::unordered_map<std::string_view, Gaussian3> combined;
  for (const auto& [object, rows] : rows_of_object) {
    combined.emplace(object, registration_.active() ? registration_.combine(rows)
                                                    : information_weighted_mean(measurements_of_object.at(object)));
  }

  std::vector<Gaussian3> estimates;
  estimates.reserve(measurements.size());
  const auto history_limit = static_cast<std::size_t>(predictor_.history_positions());
  last_predictions_.assign(measurements.size(), std::nullopt);
  const ProcessNoiseScale scale = process_noise_scale_;  // λ from the earlier steps
  struct Innovation {
    Vector3d value;
    Matrix3d known_covariance;  // P̂_last + R
    Matrix3d process_noise;     // Q(Δt)
  };
  std::unordered_map<std::string_view, Innovation> innovation_of_object;  // the object's first such row
  for (std::size_t row = 0; row < measurements.size(); ++row) {
    const Measurement& measurement = *measurements[row];
    Track& track = tracks_[measurement.view][measurement.object];
    std::optional<Gaussian3> prior;  // none: diffuse
    if (const auto& index = prediction_of_row[row]) {  // the track is not empty
      // P = P̂_last + Q(Δt), plus the unknown velocity's spread for a single-position track.
      const TrackPoint& last = track.back();
      const double dt = time - last.time;
      const Matrix3d process_noise = predictor_.process_noise(dt);
      Matrix3d covariance = last.estimate.covariance() + scale.scaled(process_noise);
      if (track.size() >= 2 && adapt_process_noise_ && !innovation_of_object.contains(measurement.object)) {
        const Gaussian3& observed = combined.at(measurement.object);
        innovation_of_object.emplace(
            measurement.object,
            Innovation{observed.mean() - predicted[index->first][index->second],
                       last.estimate.covariance() + observed.covariance(), process_noise});
      }
      if (track.size() == 1) {
        const double spread = predictor_.typical_speed() * dt;
        covariance += spread * spread * Matrix3d::Identity();
      }
      prior = Gaussian3::from_covariance(predicted[index->first][index->second], covariance);
      last_predictions_[row] = Prediction{prior->mean(), last.estimate.covariance(), dt, track.size()};
    }
    // The diffuse start is the limit P⁻¹ → 0 of the update: the combined measurement itself.
    const Gaussian3 fused = !prior                   ? combined.at(measurement.object)
                            : registration_.active() ? multi_view_update(*prior, std::span(&combined.at(measurement.object), 1))
                                                     : multi_view_update(*prior, measurements_of_object.at(measurement.object));
    track.push_back(TrackPoint{time, fused});
    if (track.size() > history_limit) track.pop_front();
    estimates.push_back(fused);
  }
  registration_.learn(measurements);
  // In row order (an unordered_map's order could differ between library versions).
  for (const Measurement* measurement : measurements) {
    const auto found = innovation_of_object.find(measurement->object);
    if (found == innovation_of_object.end()) continue;
    const Innovation& innovation = found->second;
    process_noise_scale_.add(innovation.value, innovation.known_covariance, innovation.process_noise);
    innovation_of_object.erase(found);
  }
  return estimates;
}

}  // namespace stgf
