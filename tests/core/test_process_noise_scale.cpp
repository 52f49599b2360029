#include "stgf/core/process_noise_scale.hpp"

#include <random>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

namespace stgf {
namespace {

// Innovations drawn from N(0, A + true_scale · B) with a fixed A and B.
double scale_after(double true_scale, int innovations, std::uint64_t seed) {
  Matrix3d known;
  known << 0.04, 0.01, 0.0, 0.01, 0.03, 0.0, 0.0, 0.0, 0.01;
  Matrix3d process;
  process << 0.02, 0.005, 0.0, 0.005, 0.01, 0.0, 0.0, 0.0, 0.001;
  const Matrix3d factor = Matrix3d(known + true_scale * process).llt().matrixL();
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal;
  ProcessNoiseScale scale;
  for (int k = 0; k < innovations; ++k) {
    scale.add(factor * Vector3d(normal(random), normal(random), normal(random)), known, process);
  }
  EXPECT_EQ(scale.innovations(), static_cast<std::size_t>(innovations));
  return scale.scale();
}

TEST(ProcessNoiseScale, StartsAtOne) { EXPECT_EQ(ProcessNoiseScale().scale(), 1.0); }

TEST(ProcessNoiseScale, StaysNearOneWhenQIsRight) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const double scale = scale_after(1.0, 400, seed);
    EXPECT_GE(scale, 1.0);
    EXPECT_LE(scale, 1.5) << "seed " << seed;
  }
}

TEST(ProcessNoiseScale, FindsAQThatIsTooSmall) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const double scale = scale_after(16.0, 400, seed);
    EXPECT_GT(scale, 16.0 / 1.5) << "seed " << seed;
    EXPECT_LT(scale, 16.0 * 1.5) << "seed " << seed;
  }
}

TEST(ProcessNoiseScale, NeverShrinksQ) {
  // Innovations much smaller than A says (errors correlated between prediction and measurement).
  ProcessNoiseScale scale;
  for (int k = 0; k < 100; ++k) scale.add(Vector3d::Constant(1e-4), Matrix3d::Identity(), Matrix3d::Identity());
  EXPECT_EQ(scale.scale(), 1.0);
}

TEST(ProcessNoiseScale, AFewInnovationsMoveItLittle) {
  // One innovation of 3 σ of A alone: the prior holds λ well below what that one sample alone suggests.
  ProcessNoiseScale scale;
  scale.add(Vector3d(0.6, 0.0, 0.0), 0.04 * Matrix3d::Identity(), 0.04 * Matrix3d::Identity());
  EXPECT_LT(scale.scale(), 4.0);
}

TEST(ProcessNoiseScale, RejectsBadInput) {
  ProcessNoiseScale scale;
  EXPECT_THROW(scale.add(Vector3d::Zero(), Matrix3d::Identity(), Matrix3d::Identity(), 0.0), std::invalid_argument);
  EXPECT_THROW(scale.add(Vector3d(std::nan(""), 0, 0), Matrix3d::Identity(), Matrix3d::Identity()), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
