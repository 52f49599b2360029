// SPDX-License-Identifier: Apache-2.0
#pragma once
// A view's registration offset β = (t, δ, ε) drawn from a prior, for tests that simulate one.

#include <random>

#include <Eigen/Dense>

#include "stgf/core/view_registration.hpp"

namespace stgf::testing {

// t along the world axes with σ, δ along the axes of offset_jacobian's frame with α, ε with σ_ε.
inline OffsetVector draw_offset(const RegistrationPrior& prior, std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  OffsetVector offset;
  for (int axis = 0; axis < 3; ++axis) offset[axis] = prior.translation_sigma[axis] * normal(rng);
  for (int axis = 3; axis < 6; ++axis) offset[axis] = prior.noise_ratio[axis - 3] * normal(rng);
  offset[6] = prior.range_scale_sigma * normal(rng);
  return offset;
}

}  // namespace stgf::testing
