// SPDX-License-Identifier: Apache-2.0
#pragma once
// stgf-learned's side of learned_seam.hpp: any method by name (stgf/model/named_methods.hpp), with
// what the run did logged for the user (stgf run with a learned method, stgf reproduce).

#include <span>
#include <string>
#include <vector>

#include "learned_seam.hpp"
#include "stgf/core/records.hpp"
#include "stgf/model/trained_motion_model.hpp"
#include "stgf/model/named_methods.hpp"
#include "stgf/methods/registry.hpp"

namespace stgf::cli {

// One log line for each thing the user should know of a run: a model without registration
// calibration, restarted tracks, what the gate did, rewinds for late rows, rows left out as too late.
void log_method_report(const std::string& method, const MethodConfig& config, const TrainedMotionModel* model,
                       const std::string& model_path, const MethodRunReport& report);

// stgf::run_named_method over a whole list, then log_method_report.
std::vector<Gaussian3> run_method_and_log(const std::string& method, const MethodConfig& config, const TrainedMotionModel* model,
                                          const std::string& model_path, std::span<const Measurement> rows);

}  // namespace stgf::cli
