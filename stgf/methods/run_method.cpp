// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/run_method.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include "stgf/core/steps.hpp"

namespace stgf {

std::vector<Gaussian3> run_method(const std::string& name, const MethodConfig& config,
                                  std::span<const Measurement> measurements, GatingSummary* gating) {
  const auto& names = method_names();
  if (std::find(names.begin(), names.end(), name) == names.end()) make_localizer(name, config);  // throws: unknown name
  return run_localizer([&] { return make_localizer(name, config); }, measurements, gating);
}

std::vector<Gaussian3> run_localizer(const std::function<std::unique_ptr<Localizer>()>& make_scene_localizer,
                                     std::span<const Measurement> measurements, GatingSummary* gating) {
  std::vector<std::optional<Gaussian3>> estimates(measurements.size());
  std::vector<const Measurement*> step_measurements;
  for (const Scene& scene : group_into_scenes(measurements)) {
    const std::unique_ptr<Localizer> localizer = make_scene_localizer();
    for (const Step& step : scene.steps) {
      step_measurements.clear();
      for (std::size_t row : step.rows) step_measurements.push_back(&measurements[row]);
      std::vector<Gaussian3> step_estimates = localizer->step(step.time, step_measurements);
      if (step_estimates.size() != step.rows.size()) {
        throw std::logic_error("a localizer returned the wrong number of estimates");
      }
      for (std::size_t k = 0; k < step.rows.size(); ++k) estimates[step.rows[k]] = step_estimates[k];
    }
    if (gating != nullptr) localizer->report_gating(scene.name, *gating);
  }
  std::vector<Gaussian3> result;
  result.reserve(estimates.size());
  for (const auto& estimate : estimates) result.push_back(*estimate);
  return result;
}

}  // namespace stgf
