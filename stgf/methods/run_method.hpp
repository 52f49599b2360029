// SPDX-License-Identifier: Apache-2.0
#pragma once
// Runs a method over a whole measurement set: a fresh Localizer per scene, steps in time order.

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "stgf/methods/registry.hpp"

namespace stgf {

// One estimate per measurement row, in the order of `measurements`, from a fresh Localizer made by
// `make_scene_localizer()` for every scene.
// What the localizers' gates did goes to `gating` when given.
std::vector<Gaussian3> run_localizer(const std::function<std::unique_ptr<Localizer>()>& make_scene_localizer,
                                     std::span<const Measurement> measurements, GatingSummary* gating = nullptr);

// run_localizer with the named model-based method.
std::vector<Gaussian3> run_method(const std::string& name, const MethodConfig& config,
                                  std::span<const Measurement> measurements, GatingSummary* gating = nullptr);

}  // namespace stgf
