#pragma once
// Runs a method over a whole measurement set: a fresh Localizer per scene, steps in time order.

#include <span>
#include <string>
#include <vector>

#include "stgf/methods/registry.hpp"

namespace stgf {

// One estimate per measurement row, in the order of `measurements`.
std::vector<Gaussian3> run_method(const std::string& name, const MethodConfig& config,
                                  std::span<const Measurement> measurements);

}  // namespace stgf
