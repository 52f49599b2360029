// SPDX-License-Identifier: Apache-2.0
#pragma once
// stgf-learned's side of learned_seam.hpp: any method by name (stgf/learn/named_methods.hpp), with
// what the run did logged for the user (stgf run with a learned method, stgf reproduce).

#include <span>
#include <string>
#include <vector>

#include "learned_seam.hpp"
#include "stgf/core/records.hpp"
#include "stgf/learn/motion_model.hpp"
#include "stgf/learn/named_methods.hpp"
#include "stgf/methods/registry.hpp"

namespace stgf::cli {

// stgf::run_named_method, then one log line for each thing the user should know: restarted tracks,
// rewinds for late rows, rows left out as too late, a model without registration calibration.
std::vector<Gaussian3> run_method_and_log(const std::string& method, const MethodConfig& config, const MotionModel* model,
                                          const std::string& model_path, std::span<const Measurement> rows);

}  // namespace stgf::cli
