// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/filter_runner.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "stgf/core/common_translation_scale.hpp"
#include "stgf/core/scene_epochs.hpp"
#include "stgf/core/steps.hpp"

namespace stgf {
namespace {

// Graphs per predictor pass: large enough to amortise a pass, small enough to bound its memory.
constexpr std::size_t kGraphsPerPass = 4096;

// The deliveries of a scene: groups of row indices, in the order the filter receives them.
std::vector<std::vector<std::size_t>> deliveries_of(const Scene& scene, std::span<const Measurement> measurements,
                                                    bool by_arrival) {
  std::vector<std::vector<std::size_t>> deliveries;
  if (!by_arrival) {
    for (const Step& step : scene.steps) deliveries.push_back(step.rows);
    return deliveries;
  }
  std::vector<std::size_t> rows;
  for (const Step& step : scene.steps) rows.insert(rows.end(), step.rows.begin(), step.rows.end());
  std::stable_sort(rows.begin(), rows.end(), [&](std::size_t a, std::size_t b) {
    const Measurement& x = measurements[a];
    const Measurement& y = measurements[b];
    if (*x.arrival != *y.arrival) return *x.arrival < *y.arrival;
    if (x.time != y.time) return x.time < y.time;
    return a < b;
  });
  for (std::size_t row : rows) {
    if (deliveries.empty() || *measurements[deliveries.back().front()].arrival != *measurements[row].arrival) {
      deliveries.emplace_back();
    }
    deliveries.back().push_back(row);
  }
  return deliveries;
}

struct SceneRun {
  std::string name;
  std::unique_ptr<SceneFilter> filter;
  std::vector<std::vector<std::size_t>> deliveries;
  std::size_t next = 0;
  bool raised = false;  // some report carried the run's size of the common translation
};

// Rows whose estimate has come, so that a row left without one is caught.
using Estimated = std::vector<bool>;

// `results`: scratch, reused from call to call. `reported_addition`: what the estimates' covariances
// carry beyond the filter's (common_translation_scale.hpp). Whether some result carried it.
bool collect(SceneFilter& filter, std::vector<SceneFilter::Result>& results, Estimated& estimated,
             FilterRun& run, bool keep_predictions, const Matrix3d& reported_addition) {
  filter.take_results(results);
  const bool adds = !reported_addition.isZero(0.0);
  for (SceneFilter::Result& result : results) {
    run.estimates[result.id] =
        adds ? Gaussian3::from_covariance(result.estimate.mean(),
                                          result.estimate.covariance() + reported_addition)
             : result.estimate;
    estimated[result.id] = true;
    if (!keep_predictions) continue;
    run.predictions[result.id] = result.prediction ? std::optional(*result.prediction) : std::nullopt;
    if (adds && result.prediction) {  // ours-l reports the prediction: the same common translation
      Gaussian3& prior = run.predictions[result.id]->prior;
      prior = Gaussian3::from_covariance(prior.mean(), prior.covariance() + reported_addition);
    }
  }
  return adds && !results.empty();
}

// What the pools gave the block (its scenes' sensors all fixed or all moving), and where its first
// scene is in the whole run.
struct PooledScales {
  RegistrationScalePool* registration = nullptr;  // the pool of the block's kind of sensor
  ProcessNoisePool* process_noise = nullptr;
  SensorMotion sensors = SensorMotion::kFixed;
  std::size_t first_scene = 0;
  std::optional<RegistrationScalePool::Point> applied;  // none: each scene learns its own registration scales
  // The common translation's size from the run's scenes (common_translation_scale.hpp): where the
  // scenes' κ̂_t go, κ̂_run for the block (none: nothing added), and the calibration's σ_t.
  CommonTranslationScale* common_translation = nullptr;
  std::optional<double> common_run_scale;
  Vector3d translation_sigma = Vector3d::Zero();
};

// A scene's κ̂_t relative to the calibration: the run's lowered scale times the scene's own (1 until
// it has learned one).
double translation_scale(const SceneFilter& filter, const PooledScales& pooled) {
  const double applied = pooled.applied ? pooled.applied->scales().translation : 1.0;
  return filter.registration_prior_scale_learned() ? applied * filter.registration_prior_scales().translation
                                                   : applied;
}

// What the scene's reports add to the filter's covariance (zero without κ̂_run).
Matrix3d reported_addition(const SceneFilter& filter, const PooledScales& pooled) {
  if (!pooled.common_run_scale) return Matrix3d::Zero();
  return common_translation_addition(pooled.translation_sigma, *pooled.common_run_scale,
                                     translation_scale(filter, pooled), filter.registration_views());
}

void run_block(const MotionPredictor& predictor, const FilterOptions& options, std::span<const Measurement> measurements,
               std::span<const Scene> scenes, bool by_arrival, Estimated& estimated, FilterRun& run,
               bool keep_predictions, const PooledScales& pooled) {
  std::vector<SceneRun> block;
  block.reserve(scenes.size());
  for (const Scene& scene : scenes) {
    block.push_back(
        {scene.name, std::make_unique<SceneFilter>(predictor, options), deliveries_of(scene, measurements, by_arrival), 0});
  }
  std::vector<const Measurement*> delivered;
  std::vector<SceneFilter::Result> results;
  for (;;) {
    // Every scene runs until it waits for forecasts or has nothing left.
    std::vector<SceneRun*> waiting;
    std::vector<MotionGraph> graphs;
    for (SceneRun& scene : block) {
      for (;;) {
        // Until its last delivery a scene only needs each row's estimate: what a late row sends back
        // to be processed again waits for the rows after it (SceneFilter::Advance).
        const bool done = scene.filter->advance(scene.next == scene.deliveries.size()
                                                    ? SceneFilter::Advance::kThroughEverything
                                                    : SceneFilter::Advance::kUntilReported);
        if (collect(*scene.filter, results, estimated, run, keep_predictions,
                    reported_addition(*scene.filter, pooled))) {
          scene.raised = true;
        }
        if (!done) {
          waiting.push_back(&scene);
          const auto& request = scene.filter->forecast_request();
          graphs.insert(graphs.end(), request.begin(), request.end());
          break;
        }
        if (scene.next == scene.deliveries.size()) break;
        const std::vector<std::size_t>& rows = scene.deliveries[scene.next++];
        delivered.clear();
        for (std::size_t row : rows) delivered.push_back(&measurements[row]);
        scene.filter->receive(delivered, rows);
      }
    }
    if (waiting.empty()) break;
    std::vector<std::vector<MotionForecast>> forecasts;
    forecasts.reserve(graphs.size());
    for (std::size_t first = 0; first < graphs.size(); first += kGraphsPerPass) {
      const std::size_t count = std::min(kGraphsPerPass, graphs.size() - first);
      for (auto& of_graph : predictor.forecast(std::span(graphs).subspan(first, count))) {
        forecasts.push_back(std::move(of_graph));
      }
    }
    std::size_t next_graph = 0;
    for (SceneRun* scene : waiting) {
      const std::size_t count = scene->filter->forecast_request().size();
      const std::vector<std::vector<MotionForecast>> own(forecasts.begin() + static_cast<std::ptrdiff_t>(next_graph),
                                                         forecasts.begin() + static_cast<std::ptrdiff_t>(next_graph + count));
      scene->filter->provide_forecasts(own);
      next_graph += count;
    }
  }
  for (std::size_t s = 0; s < block.size(); ++s) {
    const SceneRun& scene = block[s];
    if (pooled.registration != nullptr) {
      const std::vector<double> grid = scene.filter->registration_likelihood_grid();
      if (!grid.empty()) {
        pooled.registration->add(pooled.first_scene + s, grid, pooled.applied.value_or(RegistrationScalePool::Point{}));
      }
    }
    if (pooled.process_noise != nullptr) {
      pooled.process_noise->add(pooled.first_scene + s, scene.filter->process_noise_evidence());
    }
    run.restarted_tracks += scene.filter->restarted_tracks();
    run.coasting_predictions += scene.filter->coasting_predictions();
    run.late_measurements += scene.filter->late_measurements();
    run.late_rows += scene.filter->late_rows();
    run.rewinds += scene.filter->rewinds();
    run.gating.add(scene.name, scene.filter->view_noise_scales());
    run.gating.restarts += scene.filter->gate_restarts();
    run.gating.refilters += scene.filter->refilters();
    run.motion_choice.add(scene.filter->motion_choice());
    if (options.adapt_registration_prior && !options.registration.is_zero() && options.tracks == TrackMode::kPerObject) {
      // The scales relative to the model's calibration: the run's, times the scene's own on top.
      const RegistrationPriorScales applied = pooled.applied ? pooled.applied->scales() : RegistrationPriorScales{};
      const bool learned = scene.filter->registration_prior_scale_learned();
      LearnedRegistrationScales& record = run.registration_prior_scales[pooled.sensors];
      if (pooled.applied && !learned) {
        record.scales.push_back(applied);
      } else if (learned) {
        const RegistrationPriorScales own = scene.filter->registration_prior_scales();
        RegistrationPriorScales both = own;
        both.translation *= applied.translation;
        both.noise_ratio *= applied.noise_ratio;
        both.along *= applied.along;
        both.across *= applied.across;
        both.vertical *= applied.vertical;
        record.scales.push_back(both);
      } else {
        ++record.scenes_without;
      }
      if (pooled.common_translation != nullptr && (learned || pooled.applied)) {
        const double scale = translation_scale(*scene.filter, pooled);
        pooled.common_translation->add(pooled.first_scene + s, scale);
      }
      if (scene.raised) ++record.common_translation_raised;
      if (pooled.common_run_scale) record.common_translation_run_scale = *pooled.common_run_scale;
    }
  }
}

}  // namespace

FilterRun run_spatiotemporal_graph_filter(const MotionPredictor& predictor, const FilterOptions& options,
                                          std::span<const Measurement> measurements, bool keep_predictions,
                                          ScenePools pools, std::size_t first_scene) {
  const auto with_arrival = std::count_if(measurements.begin(), measurements.end(),
                                          [](const Measurement& measurement) { return measurement.arrival.has_value(); });
  if (with_arrival != 0 && static_cast<std::size_t>(with_arrival) != measurements.size()) {
    throw std::invalid_argument("either every measurement has an arrival time or none has");
  }
  const bool by_arrival = with_arrival != 0;
  FilterOptions scene_options = options;
  // Steps in time order leave nothing to go back for, but the gate's re-filtering of a view whose
  // noise was understated or whose offset jumped (scene_filter.hpp).
  if (!by_arrival && !options.gate.enabled) scene_options.lag_window = 0.0;
  scene_options.report_predictions = keep_predictions;
  const std::vector<Scene> scenes = group_into_scenes(measurements);
  FilterRun run;
  // One vector of estimates, each row's own measurement until its estimate comes (a Gaussian3 has no
  // empty state; a vector of optionals beside it would hold every estimate twice).
  run.estimates.reserve(measurements.size());
  for (const Measurement& measurement : measurements) run.estimates.push_back(measurement.position);
  Estimated estimated(measurements.size(), false);
  if (keep_predictions) run.predictions.resize(measurements.size());
  run.scenes = scenes.size();
  if (!(scene_options.adapt_registration_prior && !scene_options.registration.is_zero() &&
        scene_options.tracks == TrackMode::kPerObject)) {
    pools.registration = {};
    pools.common_translation = {};
  }
  if (!scene_options.adapt_process_noise) pools.process_noise = nullptr;  // λ = 1
  std::vector<SensorMotion> sensors;
  sensors.reserve(scenes.size());
  for (const Scene& scene : scenes) sensors.push_back(sensor_motion(measurements, scene));
  const bool pooling = pools.registration.fixed != nullptr || pools.registration.moving != nullptr ||
                       pools.common_translation.fixed != nullptr ||
                       pools.common_translation.moving != nullptr || pools.process_noise != nullptr;
  for (std::size_t first = 0; first < scenes.size();) {
    std::size_t count = std::min(kScenesPerFilterBlock, scenes.size() - first);
    const std::size_t global = first_scene + first;
    const SensorMotion kind = sensors[first];
    PooledScales pooled{.registration = pools.registration[kind],
                        .process_noise = pools.process_noise,
                        .sensors = kind,
                        .first_scene = global,
                        .applied = std::nullopt,
                        .common_translation = pools.common_translation[kind],
                        .common_run_scale = std::nullopt,
                        .translation_sigma = scene_options.registration.translation_sigma};
    if (pooled.common_translation != nullptr)
      pooled.common_run_scale = pooled.common_translation->run_scale_for(global);
    FilterOptions block_options = scene_options;
    block_options.sensors = kind;  // known from all the scene's rows (a streaming filter learns it as rows come)
    if (pooling) {
      // A block within one epoch of the pools: its scenes share their start.
      count = std::min(count, scene_epoch_end(global) - global);
    }
    // And of one kind of sensor: they share the pool of the registration's scales too.
    std::size_t same_kind = 1;
    while (same_kind < count && sensors[first + same_kind] == kind) ++same_kind;
    count = same_kind;
    if (pools.process_noise != nullptr) {
      block_options.process_noise_pooled = true;
      block_options.process_noise_below_one = pools.process_noise->below_one();
      if (auto start = pools.process_noise->evidence_for(global)) {
        block_options.process_noise_start = std::make_shared<const ProcessNoiseEvidence>(std::move(*start));
      }
    }
    if (pooled.registration != nullptr && pooled.registration->use() == RegistrationScalePool::Use::kEvidence) {
      // Each scene starts from the evidence of the epochs before its own and learns on from its own.
      if (auto start = pooled.registration->evidence_for(global)) {
        block_options.registration_scale_start = std::make_shared<const std::vector<double>>(std::move(*start));
      }
    } else if (pooled.registration != nullptr) {
      // Lowered only: the prior scaled down to the run's scales, each scene learning its own from there.
      pooled.applied = pooled.registration->estimate_for(global);
      if (pooled.applied) {
        const RegistrationPriorScales scales = pooled.applied->scales();
        RegistrationPrior& prior = block_options.registration;
        // The vertical offsets (σ_z, α's vertical component) by κ_v (registration_prior_scale.hpp).
        prior.translation_sigma = prior.translation_sigma.cwiseProduct(
            Vector3d(std::sqrt(scales.translation), std::sqrt(scales.translation), std::sqrt(scales.vertical)));
        prior.noise_ratio = prior.noise_ratio.cwiseProduct(
            Vector3d(std::sqrt(scales.along), std::sqrt(scales.across), std::sqrt(scales.vertical)));
        prior.range_scale_sigma *= std::sqrt(scales.noise_ratio);
      }
    }
    run_block(predictor, block_options, measurements, std::span(scenes).subspan(first, count), by_arrival, estimated,
              run, keep_predictions, pooled);
    first += count;
  }
  if (std::find(estimated.begin(), estimated.end(), false) != estimated.end()) {
    throw std::logic_error("run_spatiotemporal_graph_filter: a row got no estimate");
  }
  return run;
}

}  // namespace stgf
