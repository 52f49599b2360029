#include "stgf/learn/learned_methods.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <unordered_map>

#include "stgf/core/multi_view_update.hpp"
#include "stgf/core/steps.hpp"

namespace stgf {
namespace {

constexpr std::size_t kGraphsPerForwardPass = 4096;

// The fused measurement (information-weighted mean of all views) of the object of every row that
// `needed` marks, at the row's step; nullopt for the other rows. Only objects with such a row are fused.
std::vector<std::optional<Gaussian3>> fused_measurements(std::span<const Measurement> measurements,
                                                         const std::vector<bool>& needed) {
  std::vector<std::optional<Gaussian3>> fused(measurements.size());
  for (const Scene& scene : group_into_scenes(measurements)) {
    for (const Step& step : scene.steps) {
      std::unordered_map<std::string_view, std::vector<std::size_t>> rows_of_object;
      for (std::size_t row : step.rows) rows_of_object[measurements[row].object].push_back(row);
      for (const auto& [object, rows] : rows_of_object) {
        if (std::none_of(rows.begin(), rows.end(), [&](std::size_t row) { return needed[row]; })) continue;
        std::vector<Gaussian3> views;
        for (std::size_t row : rows) views.push_back(measurements[row].position);
        const Gaussian3 mean = information_weighted_mean(views);
        for (std::size_t row : rows) fused[row] = mean;
      }
    }
  }
  return fused;
}

}  // namespace

HistorySource history_source_of_method(const std::string& method) {
  if (method == "sttp") return HistorySource::kRawView;
  if (method == "ours-l") return HistorySource::kFused;
  throw std::invalid_argument("not a learned prediction method: '" + method + "' (known: sttp, ours-l)");
}

std::vector<Gaussian3> run_learned_method(const std::string& method, const MotionModel& model,
                                          std::span<const Measurement> measurements, std::size_t* restarted_tracks) {
  const HistorySource source = history_source_of_method(method);
  const MotionGraphSet set = make_motion_graph_set(measurements, source, model.shape().history_length + 1,  // positions = intervals + 1
                                                   model.prediction_horizon());
  if (restarted_tracks != nullptr) *restarted_tracks = set.restarted_tracks;

  std::vector<std::vector<Vector3d>> predictions;
  predictions.reserve(set.graphs.size());
  for (std::size_t first = 0; first < set.graphs.size(); first += kGraphsPerForwardPass) {
    const std::size_t count = std::min(kGraphsPerForwardPass, set.graphs.size() - first);
    for (auto& graph : model.predict(std::span(set.graphs).subspan(first, count))) predictions.push_back(std::move(graph));
  }

  // Rows without history (first sightings) start from the fused measurement for ours-l.
  std::vector<bool> first_sighting(measurements.size());
  for (std::size_t row = 0; row < measurements.size(); ++row) first_sighting[row] = !set.predictor_of_row[row];
  const std::vector<std::optional<Gaussian3>> starts = source == HistorySource::kFused
                                                           ? fused_measurements(measurements, first_sighting)
                                                           : std::vector<std::optional<Gaussian3>>{};
  const double speed = model.normalisation().speed;
  std::vector<Gaussian3> estimates;
  estimates.reserve(measurements.size());
  for (std::size_t row = 0; row < measurements.size(); ++row) {
    const auto& index = set.predictor_of_row[row];
    if (!index) {
      estimates.push_back(source == HistorySource::kFused ? *starts[row] : measurements[row].position);
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
