// SPDX-License-Identifier: Apache-2.0
// The joint registration's dense kernels (core/dense_kernels.hpp) against Eigen's own: the Cholesky
// factor on both sides of the hand-over to Eigen's blocked LLT, failure on what is not positive
// definite, forward substitution (also from the first nonzero row), the solve, and the rank-3
// updates of a lower triangle.

#include "stgf/core/dense_kernels.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace stgf {
namespace {

Eigen::MatrixXd random_spd(Eigen::Index size, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd x(size, size + 3);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = normal(random);
  return x * x.transpose() + 0.1 * Eigen::MatrixXd::Identity(size, size);
}

Eigen::MatrixXd random_matrix(Eigen::Index rows, Eigen::Index columns, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd x(rows, columns);
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] = normal(random);
  return x;
}

TEST(DenseKernels, FactorIsEigensCholeskyBelowAndAboveTheHandOver) {
  for (const Eigen::Index size : {Eigen::Index{1}, Eigen::Index{2}, Eigen::Index{7}, Eigen::Index{35},
                                  kBlockedFactorOrder - 1, kBlockedFactorOrder, kBlockedFactorOrder + 20}) {
    const Eigen::MatrixXd m = random_spd(size, static_cast<std::uint64_t>(size));
    Eigen::MatrixXd a = m;
    a.triangularView<Eigen::StrictlyUpper>().setConstant(7.0);  // never read, never written
    ASSERT_TRUE(factor_lower(a)) << size;
    const Eigen::MatrixXd expected = Eigen::LLT<Eigen::MatrixXd>(m).matrixL();
    const Eigen::MatrixXd actual = a.triangularView<Eigen::Lower>();
    EXPECT_LE((actual - expected).norm(), 1e-12 * expected.norm()) << size;
    if (size > 1) {
      EXPECT_EQ(a(0, size - 1), 7.0) << size;
    }
  }
}

TEST(DenseKernels, FactorFailsOnWhatIsNotPositiveDefinite) {
  for (const Eigen::Index size : {Eigen::Index{3}, Eigen::Index{40}, kBlockedFactorOrder + 1}) {
    Eigen::MatrixXd indefinite = random_spd(size, 3);
    indefinite(size - 1, size - 1) = -1.0;
    EXPECT_FALSE(factor_lower(indefinite)) << size;
    Eigen::MatrixXd singular = Eigen::MatrixXd::Zero(size, size);
    EXPECT_FALSE(factor_lower(singular)) << size;
    Eigen::MatrixXd with_nan = random_spd(size, 4);
    with_nan(size / 2, size / 2) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(factor_lower(with_nan)) << size;
  }
}

TEST(DenseKernels, SubstitutionAndSolveInvertTheFactor) {
  const Eigen::MatrixXd m = random_spd(30, 5);
  Eigen::MatrixXd factor = m;
  ASSERT_TRUE(factor_lower(factor));
  const Eigen::MatrixXd lower = factor.triangularView<Eigen::Lower>();
  Eigen::Matrix<double, Eigen::Dynamic, 3> x = random_matrix(30, 3, 6);
  const Eigen::Matrix<double, Eigen::Dynamic, 3> right_side = x;
  forward_substitute(factor, x);
  EXPECT_LE((lower * x - right_side).norm(), 1e-10);
  // Zero rows at the top: starting below them gives the same bits.
  Eigen::Matrix<double, Eigen::Dynamic, 6> selector = Eigen::Matrix<double, Eigen::Dynamic, 6>::Zero(30, 6);
  selector.middleRows(12, 6) = random_matrix(6, 6, 11);
  Eigen::Matrix<double, Eigen::Dynamic, 6> from_top = selector, from_first = selector;
  forward_substitute(factor, from_top);
  forward_substitute(factor, from_first, 12);
  EXPECT_EQ(from_first, from_top);
  Eigen::VectorXd b = random_matrix(30, 1, 7);
  const Eigen::VectorXd original = b;
  solve_factored(factor, b);
  EXPECT_LE((m * b - original).norm(), 1e-9 * original.norm());
}

TEST(DenseKernels, RankThreeUpdatesTouchTheLowerTriangleOnly) {
  const Eigen::MatrixXd m = random_spd(20, 8);
  const Eigen::MatrixXd a = random_matrix(20, 3, 9), b = random_matrix(20, 3, 10);
  Eigen::MatrixXd difference = m, added = m, subtracted = m;
  add_rank3_difference(difference, a, b);
  add_rank3(added, a, 1.0);
  add_rank3(subtracted, b, -1.0);
  const auto lower = [](const Eigen::MatrixXd& x) { return Eigen::MatrixXd(x.triangularView<Eigen::Lower>()); };
  const auto strictly_upper = [](const Eigen::MatrixXd& x) { return Eigen::MatrixXd(x.triangularView<Eigen::StrictlyUpper>()); };
  EXPECT_LE((lower(difference) - lower(m + a * a.transpose() - b * b.transpose())).norm(), 1e-12);
  EXPECT_LE((lower(added) - lower(m + a * a.transpose())).norm(), 1e-12);
  EXPECT_LE((lower(subtracted) - lower(m - b * b.transpose())).norm(), 1e-12);
  EXPECT_EQ(strictly_upper(difference), strictly_upper(m));
  EXPECT_EQ(strictly_upper(added), strictly_upper(m));
}

}  // namespace
}  // namespace stgf
