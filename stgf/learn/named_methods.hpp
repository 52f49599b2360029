// SPDX-License-Identifier: Apache-2.0
#pragma once
// Every method of DESIGN §2 by name over measurement rows, the learned ones (sttp, ours-l, ours)
// included: what `stgf run`, `stgf reproduce` and the Python module call.

#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "stgf/core/records.hpp"
#include "stgf/core/view_noise_scales.hpp"
#include "stgf/core/scene_filter.hpp"
#include "stgf/learn/motion_model.hpp"
#include "stgf/methods/registry.hpp"

namespace stgf {

// Loads the model a learned method needs and checks it was trained on the right input (raw for sttp,
// fused for ours-l and ours); InputError or std::invalid_argument naming the file otherwise.
MotionModel load_model_for(const std::string& method, const std::string& model_path);

// The spatiotemporal graph filter's options from the `ours:` settings: the registration prior is the
// model's calibration (its `metadata`, an empty object without a model) with the settings' overrides
// (resolve_registration_prior; `registration_missing` as there), the rest as set.
FilterOptions filter_options_for(const OursSettings& settings, const nlohmann::json& metadata,
                                 const std::string& model_path, bool* registration_missing = nullptr);

// What a run did that its caller should tell the user about.
struct MethodRunReport {
  std::size_t restarted_tracks = 0;   // a track unseen for longer than the model's horizon started again
  std::size_t rewinds = 0;            // late rows fused in their place in time
  std::size_t late_measurements = 0;  // rows later than the lag window, left out of the fusion
  bool registration_missing = false;  // the model holds no registration calibration (offsets taken as zero)
  GatingSummary gating;               // what the χ² gate did (its restarts are in restarted_tracks too)
};

// One estimate per row, in order. `model` is required for the learned methods (std::invalid_argument
// otherwise); `model_path` names it in messages. ours-l is the filter's prediction of each row before
// the update at its time (the row's own fused estimate where there is nothing to predict from).
// A late row under LatePolicy::kStop throws LateMeasurementError.
std::vector<Gaussian3> run_named_method(const std::string& method, const MethodConfig& config, const MotionModel* model,
                                        const std::string& model_path, std::span<const Measurement> rows,
                                        MethodRunReport* report = nullptr);

}  // namespace stgf
