// SPDX-License-Identifier: Apache-2.0
#pragma once
// Every method of DESIGN §2 by name over measurement rows, the learned ones (sttp, ours-l, ours)
// included: what `stgf run`, `stgf reproduce` and the Python module call.

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "stgf/core/common_translation_scale.hpp"
#include "stgf/core/process_noise_pool.hpp"
#include "stgf/core/records.hpp"
#include "stgf/core/registration_scale_pool.hpp"
#include "stgf/core/scene_filter.hpp"
#include "stgf/core/sensor_motion.hpp"
#include "stgf/core/view_noise_scales.hpp"
#include "stgf/methods/registry.hpp"
#include "stgf/model/trained_motion_model.hpp"

namespace stgf {

// Loads the model a learned method needs and checks it was trained on the right input (raw for sttp,
// fused for ours-l and ours); InputError or std::invalid_argument naming the file otherwise. With no
// path, ours and ours-l get the general model shipped with stgf (general_model.hpp); sttp has none.
TrainedMotionModel load_model_for(const std::string& method, const std::string& model_path);

// The spatiotemporal graph filter's options from the `ours:` settings: the registration prior is the
// model's calibration (its `metadata`, an empty object without a model) with the settings' overrides
// (resolve_registration_prior; `registration_missing` as there), the rest as set.
FilterOptions filter_options_for(const OursSettings& settings, const nlohmann::json& metadata,
                                 const std::string& model_path, bool* registration_missing = nullptr);

// Where `ours` learns Q's scales (process_noise_pool.hpp): as set, or (auto) across the run's scenes
// for a model trained on several benchmarks (its metadata's `benchmark` a list of more than one): its
// one Q is a compromise between kinds of motion (pedestrians and vehicles: 300 times apart) that fits
// none of them, and the run's scenes together say which way to scale it. A model of one benchmark
// keeps at least its calibrated Q, grown across the run's scenes where they say it is too small: a
// scene too short to say so alone starts from the scenes before it (design §1.2).
ProcessNoiseScaleLearning process_noise_scale_learning_for(const OursSettings& settings, const nlohmann::json& metadata);

// Where `ours` learns the registration prior's scales for scenes of fixed or of moving sensors
// (sensor_motion.hpp): as set (for both), or (auto) where the sensors move across the run's scenes,
// each scene starting from the earlier scenes' evidence (a moving platform's rigid pose error fits the
// offsets' model), for every model; where they stand still, for a model trained on several
// benchmarks, whose prior is a compromise between sensors registered tens of times apart, only
// lowered by the scenes' estimate (a camera's height error does not fit the offsets' model, and the
// scenes together would widen the prior too far), and per scene for a model of one, whose prior was
// calibrated on cameras like the data's (design §1.7).
RegistrationScaleLearning registration_scale_learning_for(const OursSettings& settings, const nlohmann::json& metadata,
                                                          SensorMotion sensors);

// What a run did that its caller should tell the user about.
struct MethodRunReport {
  std::size_t restarted_tracks = 0;   // a track unseen for longer than the model's horizon started again
  std::size_t coasting_predictions = 0;  // by constant velocity, beyond the model's horizon
  std::size_t late_rows = 0;          // late rows fused in their place in time
  std::size_t rewinds = 0;            // times a scene went back for them
  std::size_t late_measurements = 0;  // rows later than the lag window, left out of the fusion
  bool registration_missing = false;  // the model holds no registration calibration (offsets taken as zero)
  GatingSummary gating;               // what the χ² gate did (its restarts are in restarted_tracks too)
  // The registration prior's scales of the scenes of fixed and of moving sensors (filter_runner.hpp),
  // and where they were learned (registration_scale_learning_for; ours only: set once by
  // NamedMethodRun for the whole run, not added part by part).
  PerSensorMotion<LearnedRegistrationScales> registration_prior_scales;
  PerSensorMotion<RegistrationScaleLearning> registration_scale_learning;
  MotionChoiceSummary motion_choice;              // which motion the scenes followed
  // With Q's scales learned across scenes: their λ̂ per world axis from all the run's scenes so far.
  std::optional<ProcessNoisePool::Scales> process_noise_scales_across_scenes;

  // Adds what a run over later scenes did (a list run in parts).
  void add(const MethodRunReport& later);
};

// One estimate per row, in order. `model` is required for the learned methods (std::invalid_argument
// otherwise); `model_path` names it in messages. ours-l is the filter's prediction of each row before
// the update at its time (the row's own fused estimate where there is nothing to predict from).
// A late row under LatePolicy::kStop throws LateMeasurementError.
std::vector<Gaussian3> run_named_method(const std::string& method, const MethodConfig& config, const TrainedMotionModel* model,
                                        const std::string& model_path, std::span<const Measurement> rows,
                                        MethodRunReport* report = nullptr);

class SingleViewPredictionStream;  // learned_methods.hpp

// run_named_method over a list given in parts, each part whole scenes, the parts in list order (a
// file read a block of scenes at a time: `stgf run`, DESIGN §3.8). The estimates are those of one
// run over the whole list, bit for bit, whatever the parts' sizes: Φ computes each object from its own
// graph (model/motion_inference.hpp), whatever else is in a pass; `sttp` continues its passes across
// parts on its own (SingleViewPredictionStream); the other methods treat each scene alone. report()
// adds up what every part did.
class NamedMethodRun {
 public:
  // Checks as run_named_method does (a learned method without a model: std::invalid_argument).
  // `model` must outlive the run.
  NamedMethodRun(const std::string& method, const MethodConfig& config, const TrainedMotionModel* model,
                 const std::string& model_path);
  ~NamedMethodRun();

  // Takes the next part; returns the estimates now complete, one per row, in list order, following
  // those returned before: all of the part's, but for sttp, whose last pass may wait for later parts.
  // A late row under LatePolicy::kStop throws LateMeasurementError with the row's index in `rows`.
  std::vector<Gaussian3> add(std::span<const Measurement> rows);
  // The estimates of every row not returned yet.
  std::vector<Gaussian3> finish();
  const MethodRunReport& report() const { return report_; }

 private:
  std::string method_;
  MethodConfig config_;
  const TrainedMotionModel* model_;
  std::string model_path_;
  std::unique_ptr<SingleViewPredictionStream> single_view_;  // sttp
  MethodRunReport report_;
  // ours: the registration prior's scales across the run's scenes, for fixed and for moving sensors
  // (none where each scene learns its own: registration_scale_learning_for), Q's (used where
  // process_noise_scale_learning_for), and how many scenes came before the next part.
  PerSensorMotion<std::optional<RegistrationScalePool>> registration_scales_;
  std::optional<ProcessNoisePool> process_noise_scales_;
  PerSensorMotion<CommonTranslationScale> common_translation_;  // common_translation_scale.hpp
  std::size_t scenes_ = 0;
};

}  // namespace stgf
