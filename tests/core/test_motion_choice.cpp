// SPDX-License-Identifier: Apache-2.0
// The choice between the motion model and constant velocity (core/motion_choice.hpp): it follows the
// evidence of the innovations, only once that is strong, and not back without strong evidence again.

#include "stgf/core/motion_choice.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

namespace stgf {
namespace {

const Matrix3d kKnown = 0.01 * Matrix3d::Identity();   // A = P̂_s + R
const Matrix3d kProcess = 0.01 * Matrix3d::Identity();  // Q(τ) − Q(τ_s)

Vector3d draw(std::mt19937_64& random) {
  std::normal_distribution<double> normal(0.0, std::sqrt(0.02));  // N(0, A + Q)
  return {normal(random), normal(random), normal(random)};
}

TEST(MotionChoice, PerAxisLogLikelihoodIsTheSumOfTheAxes) {
  const Vector3d innovation(0.1, -0.2, 0.05);
  const Vector3d scales(1.0, 2.0, 4.0);
  double expected = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double variance = 0.01 + scales[a] * 0.01;
    expected += -0.5 * innovation[a] * innovation[a] / variance - 0.5 * std::log(2.0 * std::numbers::pi * variance);
  }
  EXPECT_NEAR(per_axis_log_likelihood(innovation, kKnown, kProcess, scales), expected, 1e-12);
}

TEST(MotionChoice, StaysWithTheModelWhileItPredictsBetter) {
  std::mt19937_64 random(1);
  MotionChoice choice(MotionFallback::kAuto);
  const ProcessNoiseScale learned;
  for (int k = 0; k < 200; ++k) {
    const Vector3d model = draw(random);
    choice.add(model, model + Vector3d(0.2, 0.0, 0.0), kKnown, kKnown, kProcess, learned, /*adapt=*/true);
    EXPECT_FALSE(choice.constant_velocity()) << "sample " << k;
  }
  EXPECT_LT(choice.evidence(), -MotionChoice::kSwitchEvidence);
  EXPECT_EQ(choice.switches(), 0u);
  EXPECT_EQ(choice.samples(), 200u);
}

TEST(MotionChoice, SwitchesOnceConstantVelocityIsFavouredByOddsOfAHundredToOne) {
  std::mt19937_64 random(2);
  MotionChoice choice(MotionFallback::kAuto);
  const ProcessNoiseScale learned;
  bool switched = false;
  for (int k = 0; k < 200; ++k) {
    const Vector3d fallback = draw(random);
    choice.add(fallback + Vector3d(0.2, 0.0, 0.0), fallback, kKnown, kKnown, kProcess, learned, /*adapt=*/true);
    // Exactly when the evidence passes ln 100, not before.
    if (!switched) {
      EXPECT_EQ(choice.constant_velocity(), choice.evidence() > MotionChoice::kSwitchEvidence);
    }
    switched = switched || choice.constant_velocity();
  }
  EXPECT_TRUE(choice.constant_velocity());
  EXPECT_EQ(choice.switches(), 1u);
}

TEST(MotionChoice, GoesBackOnlyOnStrongEvidenceForTheModel) {
  std::mt19937_64 random(3);
  MotionChoice choice(MotionFallback::kAuto);
  const ProcessNoiseScale learned;
  while (!choice.constant_velocity()) {
    const Vector3d fallback = draw(random);
    choice.add(fallback + Vector3d(0.2, 0.0, 0.0), fallback, kKnown, kKnown, kProcess, learned, /*adapt=*/false);
  }
  // Now the model is the better one: the choice holds until the evidence is ln 100 the other way.
  while (choice.constant_velocity()) {
    const double before = choice.evidence();
    const Vector3d model = draw(random);
    choice.add(model, model + Vector3d(0.2, 0.0, 0.0), kKnown, kKnown, kProcess, learned, /*adapt=*/false);
    if (choice.constant_velocity()) {
      EXPECT_GT(choice.evidence(), -MotionChoice::kSwitchEvidence);
    }
    ASSERT_LT(choice.samples(), 1000u) << "never went back; evidence " << before;
  }
  EXPECT_LT(choice.evidence(), -MotionChoice::kSwitchEvidence);
  EXPECT_EQ(choice.switches(), 2u);
}

TEST(MotionChoice, ConstantVelocityLearnsItsOwnScaleOfQ) {
  std::mt19937_64 random(4);
  MotionChoice choice(MotionFallback::kAuto);
  const ProcessNoiseScale learned;
  std::normal_distribution<double> wide(0.0, 1.0);  // far more than A + Q say
  for (int k = 0; k < 100; ++k) {
    const Vector3d fallback(wide(random), wide(random), wide(random));
    choice.add(draw(random), fallback, kKnown, kKnown, kProcess, learned, /*adapt=*/true);
  }
  EXPECT_GT(choice.fallback_scale().scales().minCoeff(), 16.0);
  EXPECT_FALSE(choice.constant_velocity());
}

TEST(MotionChoice, OnlyTheAutomaticChoiceCompares) {
  const ProcessNoiseScale learned;
  for (const MotionFallback policy : {MotionFallback::kOff, MotionFallback::kAlways}) {
    MotionChoice choice(policy);
    EXPECT_FALSE(choice.compares());
    EXPECT_EQ(choice.constant_velocity(), policy == MotionFallback::kAlways);
    EXPECT_THROW(choice.add(Vector3d::Zero(), Vector3d::Zero(), kKnown, kKnown, kProcess, learned, true), std::logic_error);
  }
  EXPECT_TRUE(MotionChoice(MotionFallback::kAuto).compares());
}

}  // namespace
}  // namespace stgf
