// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/gaussian.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

namespace stgf {
namespace {

TEST(Gaussian3, KeepsCovarianceAndItsInverse) {
  Matrix3d covariance;
  covariance << 4, 1, 0, 1, 3, 0.5, 0, 0.5, 2;
  const Gaussian3 g = Gaussian3::from_covariance(Vector3d(1, 2, 3), covariance);
  EXPECT_EQ(g.covariance(), covariance);
  EXPECT_LT((g.information() * covariance - Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_EQ(g.information(), g.information().transpose());
}

TEST(Gaussian3, FromInformationRoundTrips) {
  Matrix3d covariance;
  covariance << 4, 1, 0, 1, 3, 0.5, 0, 0.5, 2;
  const Gaussian3 a = Gaussian3::from_covariance(Vector3d(1, -2, 3), covariance);
  const Gaussian3 b = Gaussian3::from_information(a.information() * a.mean(), a.information());
  EXPECT_LT((b.mean() - a.mean()).norm(), 1e-14);
  EXPECT_LT((b.covariance() - a.covariance()).norm(), 1e-13);
}

TEST(Gaussian3, MahalanobisDistance) {
  const Gaussian3 g = Gaussian3::from_covariance(Vector3d(1, 1, 1), Vector3d(4, 9, 1).asDiagonal());
  // (2/2)² + (3/3)² + (1/1)² = 3
  EXPECT_NEAR(g.mahalanobis_squared(Vector3d(3, 4, 2)), 3.0, 1e-14);
}

TEST(CovarianceProblem, AcceptsSymmetricPositiveDefinite) {
  EXPECT_EQ(covariance_problem(Matrix3d::Identity()), std::nullopt);
  EXPECT_EQ(covariance_problem(Vector3d(1e-6, 1, 1e5).asDiagonal()), std::nullopt);
}

TEST(CovarianceProblem, RejectsIndefinite) {
  Matrix3d indefinite;
  indefinite << 1, 2, 0, 2, 1, 0, 0, 0, 1;  // eigenvalues −1, 1, 3
  const auto problem = covariance_problem(indefinite);
  ASSERT_TRUE(problem);
  EXPECT_NE(problem->find("not positive definite"), std::string::npos) << *problem;
  EXPECT_NE(problem->find("-1"), std::string::npos) << *problem;
}

TEST(CovarianceProblem, RejectsSemidefiniteZeroAndNearlySingular) {
  EXPECT_TRUE(covariance_problem(Vector3d(1, 1, 0).asDiagonal()));
  EXPECT_TRUE(covariance_problem(Matrix3d::Zero()));
  EXPECT_TRUE(covariance_problem(Vector3d(1, 1, 1e-14).asDiagonal()));
}

TEST(CovarianceProblem, RejectsAsymmetricAndNonFinite) {
  Matrix3d asymmetric = Matrix3d::Identity();
  asymmetric(0, 1) = 0.5;
  EXPECT_TRUE(covariance_problem(asymmetric));
  Matrix3d with_nan = Matrix3d::Identity();
  with_nan(2, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(covariance_problem(with_nan));
  Matrix3d with_inf = Matrix3d::Identity();
  with_inf(1, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(covariance_problem(with_inf));
}

TEST(Gaussian3, ConstructionValidates) {
  EXPECT_THROW(Gaussian3::from_covariance(Vector3d::Zero(), -Matrix3d::Identity()), std::invalid_argument);
  EXPECT_THROW(Gaussian3::from_covariance(Vector3d(std::nan(""), 0, 0), Matrix3d::Identity()),
               std::invalid_argument);
  EXPECT_THROW(Gaussian3::from_information(Vector3d::Zero(), Matrix3d::Zero()), std::invalid_argument);
}

// averaged_over_headings is the mean of T M Tᵀ over every turn T about the vertical axis.
TEST(Gaussian, AveragedOverHeadingsIsTheMeanOverTurnsAboutTheVertical) {
  Matrix3d m;
  m << 0.5, 0.1, 0.05, 0.1, 0.2, -0.02, 0.05, -0.02, 0.3;
  Matrix3d mean = Matrix3d::Zero();
  const int turns = 360;
  for (int k = 0; k < turns; ++k) {
    const Matrix3d t = Eigen::AngleAxisd(2.0 * std::numbers::pi * k / turns, Vector3d::UnitZ()).toRotationMatrix();
    mean += t * m * t.transpose() / turns;
  }
  EXPECT_LT((averaged_over_headings(m) - mean).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(averaged_over_headings(m)(0, 0), 0.35);
  EXPECT_DOUBLE_EQ(averaged_over_headings(m)(2, 2), 0.3);
}

}  // namespace
}  // namespace stgf
