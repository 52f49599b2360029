// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/gaussian_noise.hpp"

#include <stdexcept>

#include "stgf/core/cholesky3.hpp"


namespace stgf {

Vector3d draw_gaussian_error(RandomStream& random, const Matrix3d& covariance) {
  const Cholesky3 cholesky(covariance);
  if (!cholesky.ok()) throw std::invalid_argument("draw_gaussian_error: covariance is not positive definite");
  // Separate statements: the order of the draws must not depend on the compiler.
  const double xi0 = random.normal();
  const double xi1 = random.normal();
  const double xi2 = random.normal();
  return cholesky.matrix_l() * Vector3d(xi0, xi1, xi2);
}

}  // namespace stgf
