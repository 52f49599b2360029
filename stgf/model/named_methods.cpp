// SPDX-License-Identifier: Apache-2.0
#include "stgf/model/named_methods.hpp"

#include <iterator>
#include <stdexcept>

#include "stgf/model/general_model.hpp"
#include "stgf/model/learned_methods.hpp"
#include "stgf/model/registration_metadata.hpp"
#include "stgf/methods/filter_runner.hpp"
#include "stgf/methods/run_method.hpp"

namespace stgf {

TrainedMotionModel load_model_for(const std::string& method, const std::string& model_path) {
  const std::string wanted = method == "sttp" ? "raw" : "fused";
  if (model_path.empty()) {
    // The shipped model learned from fused histories: it serves ours and ours-l, not sttp.
    if (wanted == "raw") throw std::invalid_argument("--method " + method + " needs --model (a model trained with --input raw)");
    return general_model();
  }
  TrainedMotionModel model = TrainedMotionModel::load(model_path);
  const std::string trained = model.metadata().value("input", "");
  if (trained != wanted) {
    throw std::invalid_argument(model_path + " was trained on " + (trained.empty() ? "unknown" : trained) +
                                " histories; --method " + method + " needs a model trained with --input " + wanted);
  }
  return model;
}

FilterOptions filter_options_for(const OursSettings& settings, const nlohmann::json& metadata,
                                 const std::string& model_path, bool* registration_missing) {
  FilterOptions options;
  options.registration = resolve_registration_prior(settings, metadata, model_path, registration_missing);
  options.adapt_process_noise = settings.adapt_process_noise;
  options.motion_fallback = settings.motion_fallback;
  options.adapt_registration_prior = settings.adapt_registration_prior;
  options.cross_view_weights = settings.cross_view_weights;
  options.history_velocity_error = settings.history_velocity_error;
  options.tracks = settings.per_view_tracks ? TrackMode::kPerView : TrackMode::kPerObject;
  options.lag_window = settings.lag_window;
  options.late = settings.stop_on_late ? LatePolicy::kStop : LatePolicy::kLeaveOut;
  options.gate = settings.gate;
  return options;
}

namespace {

bool trained_on_several_benchmarks(const nlohmann::json& metadata) {
  const auto benchmark = metadata.find("benchmark");
  return benchmark != metadata.end() && benchmark->is_array() && benchmark->size() > 1;
}

}  // namespace

ProcessNoiseScaleLearning process_noise_scale_learning_for(const OursSettings& settings, const nlohmann::json& metadata) {
  if (settings.process_noise_scale_learning) return *settings.process_noise_scale_learning;
  return trained_on_several_benchmarks(metadata) ? ProcessNoiseScaleLearning::kAcrossScenes
                                                 : ProcessNoiseScaleLearning::kGrowAcrossScenes;
}

RegistrationScaleLearning registration_scale_learning_for(const OursSettings& settings, const nlohmann::json& metadata,
                                                          SensorMotion sensors) {
  if (settings.registration_scale_learning) return *settings.registration_scale_learning;
  if (sensors == SensorMotion::kMoving) return RegistrationScaleLearning::kAcrossScenes;
  return trained_on_several_benchmarks(metadata) ? RegistrationScaleLearning::kShrinkAcrossScenes
                                                 : RegistrationScaleLearning::kPerScene;
}

void MethodRunReport::add(const MethodRunReport& later) {
  restarted_tracks += later.restarted_tracks;
  coasting_predictions += later.coasting_predictions;
  late_rows += later.late_rows;
  rewinds += later.rewinds;
  late_measurements += later.late_measurements;
  registration_missing = registration_missing || later.registration_missing;
  gating.add(later.gating);
  for (SensorMotion sensors : kSensorMotions) registration_prior_scales[sensors].add(later.registration_prior_scales[sensors]);
  motion_choice.add(later.motion_choice);
  if (later.process_noise_scales_across_scenes) process_noise_scales_across_scenes = later.process_noise_scales_across_scenes;
}

std::vector<Gaussian3> run_named_method(const std::string& method, const MethodConfig& config, const TrainedMotionModel* model,
                                        const std::string& model_path, std::span<const Measurement> rows,
                                        MethodRunReport* report) {
  NamedMethodRun run(method, config, model, model_path);
  std::vector<Gaussian3> estimates = run.add(rows);
  std::vector<Gaussian3> rest = run.finish();
  estimates.insert(estimates.end(), std::make_move_iterator(rest.begin()), std::make_move_iterator(rest.end()));
  if (report != nullptr) *report = run.report();
  return estimates;
}

NamedMethodRun::NamedMethodRun(const std::string& method, const MethodConfig& config, const TrainedMotionModel* model,
                               const std::string& model_path)
    : method_(method), config_(config), model_(model), model_path_(model_path) {
  if (is_learned_method(method_) && model_ == nullptr) throw std::invalid_argument("--method " + method_ + " needs --model");
  if (method_ == "sttp") single_view_ = std::make_unique<SingleViewPredictionStream>(*model_);
  if (model_ != nullptr) {
    for (SensorMotion sensors : kSensorMotions) {
      const RegistrationScaleLearning learning = registration_scale_learning_for(config_.ours, model_->metadata(), sensors);
      report_.registration_scale_learning[sensors] = learning;
      if (learning != RegistrationScaleLearning::kPerScene) {
        registration_scales_[sensors].emplace(
            learning == RegistrationScaleLearning::kAcrossScenes
                ? RegistrationScalePool::Use::kEvidence
                : RegistrationScalePool::lowering_for(
                      resolve_registration_prior(config_.ours, model_->metadata(), model_path_)
                          .range_scale_sigma));
      }
    }
    const ProcessNoiseScaleLearning learning = process_noise_scale_learning_for(config_.ours, model_->metadata());
    if (learning != ProcessNoiseScaleLearning::kPerScene) {
      process_noise_scales_.emplace(/*below_one=*/learning == ProcessNoiseScaleLearning::kAcrossScenes);
    }
  }
}

NamedMethodRun::~NamedMethodRun() = default;

std::vector<Gaussian3> NamedMethodRun::add(std::span<const Measurement> rows) {
  if (!is_learned_method(method_)) return run_method(method_, config_, rows);
  if (single_view_) {
    std::vector<Gaussian3> estimates = single_view_->add(rows);
    report_.restarted_tracks = single_view_->restarted_tracks();
    return estimates;
  }

  MethodRunReport part;
  const FilterOptions options = filter_options_for(config_.ours, model_->metadata(), model_path_, &part.registration_missing);
  const bool prediction_only = method_ == "ours-l";
  const auto pool = [this](SensorMotion sensors) {
    std::optional<RegistrationScalePool>& scales = registration_scales_[sensors];
    return scales ? &*scales : nullptr;
  };
  const ScenePools pools{
      .registration = {.fixed = pool(SensorMotion::kFixed), .moving = pool(SensorMotion::kMoving)},
      .process_noise = process_noise_scales_ ? &*process_noise_scales_ : nullptr,
      .common_translation = {.fixed = &common_translation_.fixed, .moving = &common_translation_.moving}};
  FilterRun run = run_spatiotemporal_graph_filter(*model_, options, rows, /*keep_predictions=*/prediction_only, pools, scenes_);
  scenes_ += run.scenes;
  part.restarted_tracks = run.restarted_tracks;
  part.coasting_predictions = run.coasting_predictions;
  part.late_rows = run.late_rows;
  part.rewinds = run.rewinds;
  part.late_measurements = run.late_measurements;
  part.gating = std::move(run.gating);
  part.registration_prior_scales = std::move(run.registration_prior_scales);
  part.motion_choice = run.motion_choice;
  if (process_noise_scales_) part.process_noise_scales_across_scenes = process_noise_scales_->scales();
  report_.add(part);
  if (prediction_only) {
    for (std::size_t row = 0; row < rows.size(); ++row) {
      if (const auto& prediction = run.predictions[row]) run.estimates[row] = prediction->prior;
    }
  }
  return std::move(run.estimates);
}

std::vector<Gaussian3> NamedMethodRun::finish() {
  if (!single_view_) return {};
  std::vector<Gaussian3> estimates = single_view_->finish();
  report_.restarted_tracks = single_view_->restarted_tracks();
  return estimates;
}

}  // namespace stgf
