// SPDX-License-Identifier: Apache-2.0
#pragma once
// Any method of DESIGN §2 by name, over measurement rows, with the model loaded once (stgf-learned:
// stgf run with a learned method, stgf reproduce).

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "method_names.hpp"
#include "stgf/core/records.hpp"
#include "stgf/learn/motion_model.hpp"
#include "stgf/methods/registry.hpp"

namespace stgf::cli {

// Loads the model a learned method needs and checks it was trained on the right input (raw for sttp,
// fused for ours-l and ours); std::invalid_argument naming the file otherwise.
MotionModel load_model_for(const std::string& method, const std::string& model_path);

// One estimate per row, in order. `model` (from load_model_for) is required for the learned methods.
std::vector<Gaussian3> run_named_method(const std::string& method, const MethodConfig& config,
                                        const MotionModel* model, const std::string& model_path,
                                        std::span<const Measurement> rows);

}  // namespace stgf::cli
