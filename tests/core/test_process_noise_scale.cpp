// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/process_noise_scale.hpp"

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

namespace stgf {
namespace {

// Innovations drawn from N(0, A + true_scale · B) with a fixed A and B.
Vector3d scales_after(double true_scale, int innovations, std::uint64_t seed) {
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
  return scale.scales();
}

TEST(ProcessNoiseScale, StartsAtOne) { EXPECT_EQ(ProcessNoiseScale().scales(), Vector3d::Ones()); }

TEST(ProcessNoiseScale, StaysNearOneWhenQIsRight) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Vector3d scales = scales_after(1.0, 400, seed);
    EXPECT_GE(scales.minCoeff(), 1.0);
    EXPECT_LE(scales.head<2>().maxCoeff(), 2.0) << "seed " << seed;
    // Vertically Q is a tenth of A: the innovations hardly tell λ, and the posterior is wide.
    EXPECT_LE(scales.z(), 4.0) << "seed " << seed;
  }
}

TEST(ProcessNoiseScale, FindsAQThatIsTooSmall) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Vector3d scales = scales_after(16.0, 400, seed);
    EXPECT_GT(scales.minCoeff(), 16.0 / 2.0) << "seed " << seed;
    EXPECT_LT(scales.maxCoeff(), 16.0 * 2.0) << "seed " << seed;
  }
}

TEST(ProcessNoiseScale, NeverShrinksQ) {
  // Innovations much smaller than A says (errors correlated between prediction and measurement).
  ProcessNoiseScale scale;
  for (int k = 0; k < 100; ++k) scale.add(Vector3d::Constant(1e-4), Matrix3d::Identity(), Matrix3d::Identity());
  EXPECT_EQ(scale.scales(), Vector3d::Ones());
}

TEST(ProcessNoiseScale, AFewInnovationsMoveItLittle) {
  // One innovation of 3 σ of A alone; on its own it says λ = (0.36 − 0.04) / 0.04 = 8. The prior holds
  // λ below that, and the other axes (innovation 0) stay at 1.
  ProcessNoiseScale scale;
  scale.add(Vector3d(0.6, 0.0, 0.0), 0.04 * Matrix3d::Identity(), 0.04 * Matrix3d::Identity());
  EXPECT_GT(scale.scales().x(), 1.0);
  EXPECT_LT(scale.scales().x(), 8.0);
  EXPECT_EQ(scale.scales().y(), 1.0);
}

TEST(ProcessNoiseScale, EachAxisOnItsOwn) {
  // Only the vertical innovations are too large: only the vertical Q grows, and D Q D scales it.
  std::mt19937_64 random(3);
  std::normal_distribution<double> normal;
  ProcessNoiseScale scale;
  const Matrix3d known = 0.01 * Matrix3d::Identity();
  const Matrix3d process = 0.01 * Matrix3d::Identity();
  for (int k = 0; k < 300; ++k) {
    scale.add(Vector3d(0.14 * normal(random), 0.14 * normal(random), 0.5 * normal(random)), known, process);
  }
  EXPECT_LT(scale.scales().head<2>().maxCoeff(), 2.0);
  EXPECT_GT(scale.scales().z(), 12.0);
  const Matrix3d scaled = scale.scaled(process);
  EXPECT_NEAR(scaled(2, 2), 0.01 * scale.scales().z(), 1e-12);
  EXPECT_NEAR(scaled(0, 0), 0.01 * scale.scales().x(), 1e-12);
}

TEST(ProcessNoiseScale, RejectsBadInput) {
  ProcessNoiseScale scale;
  EXPECT_THROW(scale.add(Vector3d::Zero(), Matrix3d::Identity(), Matrix3d::Identity(), 0.0), std::invalid_argument);
  EXPECT_THROW(scale.add(Vector3d(std::nan(""), 0, 0), Matrix3d::Identity(), Matrix3d::Identity()), std::invalid_argument);
}

// Many short scenes of a motion with Q 16 times the calibrated one: each alone has too few innovations
// to reach λ = 16; started from the others' evidence (process_noise_pool.hpp), a scene is there at once,
// and what it adds is its own innovations' evidence, the same whatever it started from.
TEST(ProcessNoiseScale, StartsFromOtherScenesEvidence) {
  Matrix3d known = Matrix3d::Identity() * 0.04;
  Matrix3d process = Matrix3d::Identity() * 0.02;
  const Matrix3d factor = Matrix3d(known + 16.0 * process).llt().matrixL();
  std::mt19937_64 random(3);
  std::normal_distribution<double> normal;
  ProcessNoiseScale::Grid pooled{};
  double alone_error = 0.0;  // mean |log₂ λ̂ − log₂ 16| of the scenes alone, per axis
  for (int scene = 0; scene < 40; ++scene) {
    const ProcessNoiseScale fresh = ProcessNoiseScale::learning_the_whole_grid();
    ProcessNoiseScale from_pool(pooled);
    const ProcessNoiseScale pool_start = from_pool;
    ProcessNoiseScale alone = fresh;
    for (int k = 0; k < 3; ++k) {
      const Vector3d innovation = factor * Vector3d(normal(random), normal(random), normal(random));
      alone.add(innovation, known, process);
      from_pool.add(innovation, known, process);
    }
    const ProcessNoiseScale::Grid own = alone.evidence_since(fresh);
    const ProcessNoiseScale::Grid own_from_pool = from_pool.evidence_since(pool_start);
    for (int a = 0; a < 3; ++a) {
      for (int point = 0; point < ProcessNoiseScale::kGridPoints; ++point) {
        EXPECT_NEAR(own[a][point], own_from_pool[a][point], 1e-9 * (1.0 + std::abs(own[a][point])));
        pooled[a][point] += own[a][point];
      }
    }
    alone_error += (alone.scales().array().log2() - 4.0).abs().sum() / (3.0 * 40.0);
  }
  EXPECT_GT(alone_error, 1.0);  // 3 innovations: a scene alone is often off by more than twice
  const Vector3d started = ProcessNoiseScale(pooled).scales();
  EXPECT_GT(started.minCoeff(), 16.0 / 1.5);
  EXPECT_LT(started.maxCoeff(), 16.0 * 1.5);
  // A scene of its own weighs its innovations on λ ≥ 1 only, and its λ̂ is the same.
  ProcessNoiseScale own;
  ProcessNoiseScale whole = ProcessNoiseScale::learning_the_whole_grid();
  for (int k = 0; k < 20; ++k) {
    const Vector3d innovation = 0.1 * Vector3d(normal(random), normal(random), normal(random));
    own.add(innovation, known, process);
    whole.add(innovation, known, process);
  }
  EXPECT_EQ(own.scales(), whole.scales());
  EXPECT_EQ(own.evidence_since(ProcessNoiseScale())[0][0], 0.0);
  EXPECT_NE(whole.evidence_since(ProcessNoiseScale::learning_the_whole_grid())[0][0], 0.0);
  ProcessNoiseScale::Grid bad{};
  bad[1][3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(ProcessNoiseScale{bad}, std::invalid_argument);
}

// Started from other scenes' evidence with λ held at 1 and above (`grow-across-scenes`): where the
// scenes say Q is too small on one axis, that axis starts there, as it would below 1 allowed; where they
// say it is too large, Q stays as calibrated, and the scene's own innovations can still only raise it.
// What it adds to the pool is the same either way (weighed on the whole grid).
TEST(ProcessNoiseScale, HeldAtItsCalibrationFromOtherScenesWhereTheySayQIsTooLarge) {
  const Matrix3d known = Matrix3d::Identity() * 0.04;
  const Matrix3d process = Matrix3d::Identity() * 0.02;
  // Innovations of a motion whose Q is 16 times the calibrated one along x, a sixteenth of it along y
  // and z.
  const Vector3d truth(16.0, 1.0 / 16.0, 1.0 / 16.0);
  const Matrix3d factor = Matrix3d(known + truth.asDiagonal() * process).llt().matrixL();
  std::mt19937_64 random(5);
  std::normal_distribution<double> normal;
  ProcessNoiseScale others = ProcessNoiseScale::learning_the_whole_grid();
  for (int k = 0; k < 400; ++k) {
    others.add(factor * Vector3d(normal(random), normal(random), normal(random)), known, process);
  }
  const ProcessNoiseScale::Grid evidence = others.evidence_since(ProcessNoiseScale::learning_the_whole_grid());
  const Vector3d below = ProcessNoiseScale(evidence).scales();
  EXPECT_NEAR(std::log2(below.x()), 4.0, 0.6);
  EXPECT_LT(below.y(), 0.5);
  EXPECT_LT(below.z(), 0.5);
  ProcessNoiseScale held(evidence, /*below_one=*/false);
  EXPECT_EQ(held.scales().x(), below.x());
  EXPECT_EQ(held.scales().y(), 1.0);
  EXPECT_EQ(held.scales().z(), 1.0);
  // Innovations far smaller than Q says leave it at 1; far larger raise it.
  ProcessNoiseScale free(evidence);
  const ProcessNoiseScale held_start = held;
  const ProcessNoiseScale free_start = free;
  for (int k = 0; k < 50; ++k) {
    const Vector3d innovation(0.01 * normal(random), 0.01 * normal(random), 3.0 * normal(random));
    held.add(innovation, known, process);
    free.add(innovation, known, process);
  }
  EXPECT_EQ(held.scales().y(), 1.0);
  EXPECT_GT(held.scales().z(), 16.0);
  const ProcessNoiseScale::Grid held_own = held.evidence_since(held_start);
  const ProcessNoiseScale::Grid free_own = free.evidence_since(free_start);
  for (int a = 0; a < 3; ++a) {
    for (int point = 0; point < ProcessNoiseScale::kGridPoints; ++point) {
      EXPECT_NEAR(held_own[a][point], free_own[a][point], 1e-9 * (1.0 + std::abs(free_own[a][point])));
    }
  }
}

}  // namespace
}  // namespace stgf
