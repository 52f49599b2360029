// SPDX-License-Identifier: Apache-2.0
#include "stgf/io/evaluation_files.hpp"

#include <optional>

#include "stgf/io/estimate_file.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/scene_order.hpp"
#include "stgf/io/truth_file.hpp"

namespace stgf {
namespace {

// The evaluation read scene by scene, or nullopt with `why_not` when the files do not allow it.
std::optional<Evaluation> scene_by_scene(const std::string& truth, const std::vector<std::string>& estimates,
                                         const std::string& measurements, const ScoringStart& start,
                                         std::string& why_not) {
  if (estimates.empty()) {
    why_not = "no estimate file";
    return std::nullopt;
  }
  SceneScores scores(truth, estimates, measurements, start);
  try {
    TruthSceneReader truth_scenes = TruthSceneReader::open(truth);
    std::vector<EstimateSceneReader> estimate_scenes;
    for (const std::string& path : estimates) estimate_scenes.push_back(EstimateSceneReader::open(path));
    std::optional<MeasurementSceneReader> measurement_scenes;
    if (!measurements.empty()) measurement_scenes = MeasurementSceneReader::open(measurements);

    TruthFile truth_scene;
    std::vector<EstimateFile> estimate_scene(estimates.size());
    MeasurementFile measurement_scene;
    // The scored rows' file sets the order of the scenes; the others follow it.
    const auto scored_file_scene = [&]() -> std::optional<std::string> {
      if (measurement_scenes) {
        if (measurement_scenes->read(measurement_scene, 1) == 0) return std::nullopt;
        return measurement_scene.rows.front().scene;
      }
      if (!estimate_scenes.front().read(estimate_scene.front())) return std::nullopt;
      return estimate_scene.front().rows.front().scene;
    };
    while (const std::optional<std::string> scene = scored_file_scene()) {
      for (std::size_t k = measurement_scenes ? 0 : 1; k < estimates.size(); ++k) {
        if (!estimate_scenes[k].read(estimate_scene[k]) || estimate_scene[k].rows.front().scene != *scene) {
          why_not = estimates[k] + " does not have scene '" + *scene + "' next";
          return std::nullopt;
        }
      }
      // Without measurements, truth scenes that no estimate has are read (and checked) and passed over.
      do {
        if (!truth_scenes.read(truth_scene) || (measurement_scenes && truth_scene.rows.front().scene != *scene)) {
          why_not = truth + " does not have scene '" + *scene + "' next";
          return std::nullopt;
        }
      } while (truth_scene.rows.front().scene != *scene);
      if (!scores.add(truth_scene, estimate_scene, measurement_scenes ? &measurement_scene : nullptr)) {
        why_not = "scene '" + *scene + "' has rows that only the whole files can judge";
        return std::nullopt;
      }
    }
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      if (estimate_scenes[k].read(estimate_scene[k])) {
        why_not = estimates[k] + " has scenes the scored rows do not have";
        return std::nullopt;
      }
    }
    while (truth_scenes.read(truth_scene)) {
      if (measurement_scenes) {
        why_not = truth + " has scenes the measurements do not have";
        return std::nullopt;
      }
    }
  } catch (const SceneOrderError& error) {
    why_not = error.what();
    return std::nullopt;
  }
  std::optional<Evaluation> evaluation = scores.result();
  if (!evaluation) why_not = "no method";
  return evaluation;
}

}  // namespace

Evaluation evaluate_files(const std::string& truth, const std::vector<std::string>& estimates,
                          const std::string& measurements, const ScoringStart& start, std::string* read_whole_because) {
  std::string why_not;
  if (std::optional<Evaluation> evaluation = scene_by_scene(truth, estimates, measurements, start, why_not)) {
    if (read_whole_because != nullptr) read_whole_because->clear();
    return std::move(*evaluation);
  }
  const TruthFile truth_file = read_truth(truth);
  std::vector<EstimateFile> estimate_files;
  for (const std::string& path : estimates) estimate_files.push_back(read_estimates(path));
  std::optional<MeasurementFile> measurement_file;
  if (!measurements.empty()) measurement_file = read_measurements(measurements);
  Evaluation evaluation = evaluate(truth_file, estimate_files, measurement_file ? &*measurement_file : nullptr, start);
  if (read_whole_because != nullptr) *read_whole_because = why_not;
  return evaluation;
}

}  // namespace stgf
