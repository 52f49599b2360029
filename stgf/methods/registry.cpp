// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/registry.hpp"

#include <stdexcept>

#include "stgf/methods/average_of_measurements.hpp"
#include "stgf/methods/multi_view_kalman_tracker.hpp"
#include "stgf/methods/weighted_least_squares.hpp"

namespace stgf {

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = {"aom", "wls", "mmt"};
  return names;
}

std::unique_ptr<Localizer> make_localizer(const std::string& name, const MethodConfig& config) {
  if (name == "aom") return std::make_unique<AverageOfMeasurements>();
  if (name == "wls") return std::make_unique<WeightedLeastSquares>(config.wls_gate);
  if (name == "mmt") return std::make_unique<MultiViewKalmanTracker>(config.mmt, config.mmt_gate);
  std::string known;
  for (const std::string& known_name : method_names()) known += (known.empty() ? "" : ", ") + known_name;
  throw std::invalid_argument("unknown method '" + name + "' (known: " + known + ")");
}

const std::vector<std::string>& all_method_names() {
  static const std::vector<std::string> names = {"aom", "wls", "mmt", "sttp", "ours-l", "ours"};
  return names;
}

bool is_learned_method(const std::string& name) { return name == "sttp" || name == "ours-l" || name == "ours"; }

}  // namespace stgf
