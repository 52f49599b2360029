// SPDX-License-Identifier: Apache-2.0
#include "stgf/methods/weighted_least_squares.hpp"

#include "stgf/core/multi_view_update.hpp"
#include "stgf/methods/object_groups.hpp"

namespace stgf {

std::vector<Gaussian3> WeightedLeastSquares::step(double /*time*/,
                                                  std::span<const Measurement* const> measurements) {
  return estimate_per_object(measurements, [](const ObjectGroup& group) {
    return information_weighted_mean(group.measurements);
  });
}

}  // namespace stgf
