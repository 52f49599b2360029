// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/process_noise_curve.hpp"

#include <cmath>
#include <stdexcept>

namespace stgf {

double reference_growth(double period, double tau) {
  const double ratio = tau / period;
  return ratio <= 1.0 ? ratio : ratio * ratio;
}

double reference_shrinkage(double period, double tau) {
  const double ratio = period / tau;
  return ratio >= 1.0 ? ratio : ratio * ratio;
}

Matrix3d process_noise_at(const Matrix3d& reference, double period, std::span<const IntervalNoise> nodes, double tau) {
  if (nodes.empty() || tau <= period) return reference * reference_growth(period, tau);
  double low_interval = period;
  const Matrix3d* low = &reference;
  for (const IntervalNoise& node : nodes) {
    if (tau <= node.interval) {
      const double share = (tau * tau - low_interval * low_interval) /
                           (node.interval * node.interval - low_interval * low_interval);
      return *low + share * (node.covariance - *low);
    }
    low_interval = node.interval;
    low = &node.covariance;
  }
  const double ratio = tau / low_interval;
  return *low * (ratio * ratio * ratio);
}

void check_process_noise_nodes(std::span<const IntervalNoise> nodes, double after) {
  for (const IntervalNoise& node : nodes) {
    if (!(node.interval > after) || !std::isfinite(node.interval) || !node.covariance.allFinite()) {
      throw std::invalid_argument("process noise intervals must be finite and increase from the reference period");
    }
    after = node.interval;
  }
}

Matrix3d coasting_process_noise_at(std::span<const IntervalNoise> nodes, double tau) {
  return process_noise_at(nodes.front().covariance, nodes.front().interval, nodes.subspan(1), tau);
}

}  // namespace stgf
