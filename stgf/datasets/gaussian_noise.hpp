// SPDX-License-Identifier: Apache-2.0
#pragma once
// Simulated sensor errors drawn from exactly the covariance that is written with them, so that
// a benchmark's R is the true error covariance (apart from any bias a builder adds on purpose and
// documents as not being in R).

#include "stgf/core/gaussian.hpp"
#include "stgf/datasets/random.hpp"

namespace stgf {

// e = L ξ with covariance = L Lᵀ (Cholesky) and ξ ~ N(0, I), drawn one component at a time in a
// fixed order. Throws std::invalid_argument when covariance is not positive definite.
Vector3d draw_gaussian_error(RandomStream& random, const Matrix3d& covariance);

}  // namespace stgf
