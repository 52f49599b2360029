// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/weighted_least_squares.hpp"

#include "stgf/core/multi_view_update.hpp"
#include "stgf/methods/object_groups.hpp"

namespace stgf {

std::vector<Gaussian3> WeightedLeastSquares::step(double /*time*/,
                                                  std::span<const Measurement* const> measurements) {
  return estimate_per_object(measurements, [&](const ObjectGroup& group) {
    if (!gate_.enabled() || group.measurements.size() < 2) return information_weighted_mean(group.measurements);
    const MeasurementGate::Consensus consensus = gate_.consensus(group.measurements);
    std::vector<Gaussian3> passing;
    for (std::size_t k = 0; k < group.measurements.size(); ++k) {
      counts_.count(group.views[k], consensus.passes[k]);
      if (consensus.passes[k]) passing.push_back(group.measurements[k]);
    }
    return information_weighted_mean(passing);
  });
}

}  // namespace stgf
