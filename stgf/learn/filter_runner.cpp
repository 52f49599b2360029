#include "stgf/learn/filter_runner.hpp"

#include <algorithm>
#include <memory>

#include "stgf/core/steps.hpp"

namespace stgf {
namespace {

// Graphs per predictor pass: large enough to amortise a pass, small enough to bound its memory.
constexpr std::size_t kGraphsPerPass = 4096;
// Scenes advanced together: enough to fill the passes, few enough that their filters' state stays small.
constexpr std::size_t kScenesPerBlock = 256;

// Runs scenes[first, last) together, writing their rows' results into `estimates` and `run`.
void run_block(const MotionPredictor& predictor, const SpatiotemporalGraphFilter::Options& options,
               std::span<const Measurement> measurements, std::span<const Scene> scenes,
               std::vector<std::optional<Gaussian3>>& estimates, FilterRun& run, bool keep_predictions) {
  std::vector<std::unique_ptr<SpatiotemporalGraphFilter>> filters;
  filters.reserve(scenes.size());
  std::size_t rounds = 0;
  for (const Scene& scene : scenes) {
    filters.push_back(std::make_unique<SpatiotemporalGraphFilter>(predictor, options));
    rounds = std::max(rounds, scene.steps.size());
  }
  std::vector<std::vector<const Measurement*>> rows_of_scene(scenes.size());
  for (std::size_t round = 0; round < rounds; ++round) {
    // Every scene's graphs of this round, in scene order.
    std::vector<std::size_t> active;
    std::vector<MotionGraph> graphs;
    std::vector<std::size_t> first_graph;  // per active scene, then the end
    for (std::size_t s = 0; s < scenes.size(); ++s) {
      if (round >= scenes[s].steps.size()) continue;
      const Step& step = scenes[s].steps[round];
      rows_of_scene[s].clear();
      for (std::size_t row : step.rows) rows_of_scene[s].push_back(&measurements[row]);
      active.push_back(s);
      first_graph.push_back(graphs.size());
      for (MotionGraph& graph : filters[s]->prepare_step(step.time, rows_of_scene[s])) graphs.push_back(std::move(graph));
    }
    first_graph.push_back(graphs.size());

    std::vector<std::vector<Vector3d>> predicted;
    predicted.reserve(graphs.size());
    for (std::size_t first = 0; first < graphs.size(); first += kGraphsPerPass) {
      const std::size_t count = std::min(kGraphsPerPass, graphs.size() - first);
      for (auto& graph : predictor.predict(std::span(graphs).subspan(first, count))) predicted.push_back(std::move(graph));
    }

    for (std::size_t a = 0; a < active.size(); ++a) {
      const std::size_t s = active[a];
      const std::vector<std::vector<Vector3d>> own(predicted.begin() + static_cast<std::ptrdiff_t>(first_graph[a]),
                                                   predicted.begin() + static_cast<std::ptrdiff_t>(first_graph[a + 1]));
      const std::vector<Gaussian3> step_estimates = filters[s]->complete_step(own);
      const Step& step = scenes[s].steps[round];
      for (std::size_t k = 0; k < step.rows.size(); ++k) {
        estimates[step.rows[k]] = step_estimates[k];
        if (keep_predictions) run.predictions[step.rows[k]] = filters[s]->last_predictions()[k];
      }
    }
  }
  for (const auto& filter : filters) run.restarted_tracks += filter->restarted_tracks();
}

}  // namespace

FilterRun run_spatiotemporal_graph_filter(const MotionPredictor& predictor,
                                          const SpatiotemporalGraphFilter::Options& options,
                                          std::span<const Measurement> measurements, bool keep_predictions) {
  const std::vector<Scene> scenes = group_into_scenes(measurements);
  std::vector<std::optional<Gaussian3>> estimates(measurements.size());
  FilterRun run;
  if (keep_predictions) run.predictions.resize(measurements.size());
  for (std::size_t first = 0; first < scenes.size(); first += kScenesPerBlock) {
    const std::size_t count = std::min(kScenesPerBlock, scenes.size() - first);
    run_block(predictor, options, measurements, std::span(scenes).subspan(first, count), estimates, run,
              keep_predictions);
  }
  run.estimates.reserve(measurements.size());
  for (const auto& estimate : estimates) run.estimates.push_back(*estimate);
  return run;
}

}  // namespace stgf
