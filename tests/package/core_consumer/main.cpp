// SPDX-License-Identifier: Apache-2.0
// Fuses two views' measurements of one object with stgf's multi-view update, and checks the result
// by hand: two independent measurements with covariances I and 3·I weigh 3 : 1.
#include <cmath>
#include <cstdio>
#include <vector>

#include "stgf/core/gaussian.hpp"
#include "stgf/core/multi_view_update.hpp"
#include "stgf/version.hpp"

int main() {
  const stgf::Gaussian3 a = stgf::Gaussian3::from_covariance(stgf::Vector3d(0, 0, 0), stgf::Matrix3d::Identity());
  const stgf::Gaussian3 b = stgf::Gaussian3::from_covariance(stgf::Vector3d(4, 0, 0), 3 * stgf::Matrix3d::Identity());
  const std::vector<stgf::Gaussian3> views = {a, b};
  const stgf::Gaussian3 fused = stgf::information_weighted_mean(views);
  std::printf("stgf %s: fused x = %.3f, variance %.3f\n", stgf::kVersion, fused.mean().x(), fused.covariance()(0, 0));
  const bool right = std::abs(fused.mean().x() - 1.0) < 1e-12 && std::abs(fused.covariance()(0, 0) - 0.75) < 1e-12;
  return right ? 0 : 1;
}
