// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/error_by_variance.hpp"

#include <cmath>

namespace stgf {

void ErrorByVariance::add(const Gaussian3& estimate, const Vector3d& truth) {
  const Vector3d error = estimate.mean() - truth;
  for (int a = 0; a < 3; ++a) {
    const double variance = estimate.covariance()(a, a);
    // ilogb: ⌊log₂ P⌋ exactly, for every positive normal or subnormal double.
    Sums& bin = axes_[a][std::ilogb(variance)];
    ++bin.rows;
    bin.variance += variance;
    bin.squared_error += error[a] * error[a];
  }
}

std::array<std::vector<VarianceBin>, 3> ErrorByVariance::bins() const {
  std::array<std::vector<VarianceBin>, 3> result;
  for (int a = 0; a < 3; ++a) {
    for (const auto& [octave, sums] : axes_[a]) {
      const auto n = static_cast<double>(sums.rows);
      result[a].push_back({octave, sums.rows, sums.variance / n, sums.squared_error / n});
    }
  }
  return result;
}

}  // namespace stgf
