// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/error_by_variance.hpp"

#include <cmath>
#include <cstdint>
#include <numbers>

#include <gtest/gtest.h>

namespace stgf {
namespace {

Gaussian3 estimate(const Vector3d& mean, const Vector3d& variances) {
  return Gaussian3::from_covariance(mean, variances.asDiagonal().toDenseMatrix());
}

TEST(ErrorByVariance, BinsEachAxisByTheOctaveOfItsStatedVariance) {
  ErrorByVariance bins;
  // x: variances 1 (octave 0: [1, 2)) and 1.5 (octave 0), 2 (octave 1: its lower bound), 0.999 (octave −1).
  bins.add(estimate(Vector3d(1, 0, 0), Vector3d(1.0, 4.0, 0.25)), Vector3d::Zero());
  bins.add(estimate(Vector3d(2, 0, 0), Vector3d(1.5, 4.0, 0.25)), Vector3d::Zero());
  bins.add(estimate(Vector3d(0, 3, 0), Vector3d(2.0, 4.0, 0.25)), Vector3d::Zero());
  bins.add(estimate(Vector3d(0, 0, 0.5), Vector3d(0.999, 7.9, 0.25)), Vector3d::Zero());
  const auto axes = bins.bins();

  ASSERT_EQ(axes[0].size(), 3u);
  EXPECT_EQ(axes[0][0].octave, -1);
  EXPECT_EQ(axes[0][0].rows, 1u);
  EXPECT_EQ(axes[0][1].octave, 0);
  EXPECT_EQ(axes[0][1].rows, 2u);
  EXPECT_DOUBLE_EQ(axes[0][1].mean_variance, 1.25);
  EXPECT_DOUBLE_EQ(axes[0][1].mean_squared_error, (1.0 + 4.0) / 2);
  EXPECT_EQ(axes[0][2].octave, 1);
  EXPECT_DOUBLE_EQ(axes[0][2].mean_squared_error, 0.0);

  // y: every variance in [4, 8): one bin, the squared errors' mean 9/4.
  ASSERT_EQ(axes[1].size(), 1u);
  EXPECT_EQ(axes[1][0].octave, 2);
  EXPECT_EQ(axes[1][0].rows, 4u);
  EXPECT_DOUBLE_EQ(axes[1][0].mean_variance, (3 * 4.0 + 7.9) / 4);
  EXPECT_DOUBLE_EQ(axes[1][0].mean_squared_error, 9.0 / 4);

  ASSERT_EQ(axes[2].size(), 1u);
  EXPECT_EQ(axes[2][0].octave, -2);
  EXPECT_DOUBLE_EQ(axes[2][0].mean_squared_error, 0.25 / 4);
}

TEST(ErrorByVariance, RightCovariancesGiveARatioNearOneInEveryBin) {
  // Errors drawn with the stated variance, which spans four octaves: r²/P ≈ 1 in each.
  ErrorByVariance bins;
  std::uint64_t state = 12345;
  const auto uniform = [&] {  // a fixed LCG: the test does not depend on the standard library's engines
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) + 0.5) / 9007199254740992.0;
  };
  for (int k = 0; k < 40000; ++k) {
    const double variance = std::exp2(-10.0 + 4.0 * uniform());
    // Box–Muller: one standard normal per axis.
    Vector3d error;
    for (int a = 0; a < 3; ++a) {
      error[a] = std::sqrt(-2.0 * std::log(uniform())) * std::cos(2.0 * std::numbers::pi * uniform());
    }
    bins.add(estimate(std::sqrt(variance) * error, Vector3d::Constant(variance)), Vector3d::Zero());
  }
  for (const auto& axis : bins.bins()) {
    ASSERT_EQ(axis.size(), 4u);
    for (const VarianceBin& bin : axis) {
      EXPECT_NEAR(bin.mean_squared_error / bin.mean_variance, 1.0, 0.06) << "octave " << bin.octave;
    }
  }
}

}  // namespace
}  // namespace stgf
