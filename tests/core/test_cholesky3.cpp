// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/cholesky3.hpp"

#include <random>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "support/random_spd.hpp"

namespace stgf {
namespace {

TEST(Cholesky3, MatchesEigenOnRandomSpdMatrices) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 1000; ++trial) {
    const double scale = std::pow(10.0, (trial % 9) - 4);
    const Eigen::Matrix3d a = testing::random_spd(rng, scale, 1e4);
    const Cholesky3 cholesky(a);
    ASSERT_TRUE(cholesky.ok());
    const Eigen::LLT<Eigen::Matrix3d> reference(a);
    ASSERT_LT(testing::relative_difference(cholesky.matrix_l(), reference.matrixL().toDenseMatrix()), 1e-13);
    const Eigen::Matrix3d inverse = cholesky.inverse();
    ASSERT_EQ(inverse, inverse.transpose());
    ASSERT_LT(testing::relative_difference(inverse * a, Eigen::Matrix3d::Identity()), 1e-10);
    const Eigen::Matrix3d inverse_factor = cholesky.inverse_factor();  // L⁻¹, lower triangular
    ASSERT_TRUE(inverse_factor.triangularView<Eigen::StrictlyUpper>().toDenseMatrix().isZero(0.0));
    ASSERT_LT(testing::relative_difference(inverse_factor * cholesky.matrix_l(), Eigen::Matrix3d::Identity()), 1e-10);
  }
}

TEST(Cholesky3, RejectsMatricesThatAreNotPositiveDefinite) {
  Eigen::Matrix3d indefinite;
  indefinite << 1, 2, 0, 2, 1, 0, 0, 0, 1;
  EXPECT_FALSE(Cholesky3(indefinite).ok());
  EXPECT_FALSE(Cholesky3(Eigen::Vector3d(1, 1, 0).asDiagonal().toDenseMatrix()).ok());
  EXPECT_FALSE(Cholesky3(Eigen::Vector3d(-1, 1, 1).asDiagonal().toDenseMatrix()).ok());
  Eigen::Matrix3d with_nan = Eigen::Matrix3d::Identity();
  with_nan(2, 1) = std::nan("");
  EXPECT_FALSE(Cholesky3(with_nan).ok());
}

}  // namespace
}  // namespace stgf
