// SPDX-License-Identifier: Apache-2.0
// The rounds of Q's in-filter calibration (learn/process_noise_rounds.hpp): stable rounds damp Q
// towards what they measured, a round whose filter ran away is not used and the next steps half way
// back to the last stable Q, and the check falls back to the last stable Q.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "stgf/learn/process_noise_rounds.hpp"

namespace stgf {
namespace {

Matrix3d diagonal(double x, double y, double z) { return Vector3d(x, y, z).asDiagonal(); }

TEST(ProcessNoiseRounds, TakesTheFirstMeasurementThenMovesHalfWay) {
  ProcessNoiseRounds rounds(diagonal(0.3, 0.1, 0.005));
  EXPECT_TRUE(rounds.record(0.5, diagonal(0.2, 0.02, 0.001)));
  EXPECT_EQ(rounds.current(), diagonal(0.2, 0.02, 0.001));
  EXPECT_TRUE(rounds.record(0.55, diagonal(0.4, 0.04, 0.003)));
  EXPECT_TRUE(rounds.current().isApprox(diagonal(0.3, 0.03, 0.002), 1e-15)) << rounds.current();
  // Within kDivergenceFactor of the best error so far: stable.
  EXPECT_TRUE(rounds.record(0.99, diagonal(0.3, 0.03, 0.002)));
  const Matrix3d last = rounds.current();
  EXPECT_TRUE(rounds.check(1.0));
  EXPECT_EQ(rounds.current(), last);
}

// The case seen on cad with 5 s validation scenes: round 1's Q made the filter run away (202 m from
// 0.51 m), and its residuals asked for 10⁷ m².
TEST(ProcessNoiseRounds, StepsHalfWayBackWhenTheFilterRanAway) {
  const Matrix3d trained = diagonal(0.293, 0.118, 0.00532);
  ProcessNoiseRounds rounds(trained);
  ASSERT_TRUE(rounds.record(0.508, diagonal(0.175, 0.018, 0.000648)));
  const Matrix3d too_small = rounds.current();
  EXPECT_FALSE(rounds.record(202.0, diagonal(9.84e6, 5.75e4, 2.96e6)));
  EXPECT_TRUE(rounds.current().isApprox(0.5 * (trained + too_small), 1e-15)) << rounds.current();
  // Again: half way again, towards the same stable Q.
  EXPECT_FALSE(rounds.record(1.2, diagonal(1.0, 1.0, 1.0)));
  EXPECT_TRUE(rounds.current().isApprox(0.75 * trained + 0.25 * too_small, 1e-15)) << rounds.current();
  // Stable again: damped from there.
  const Matrix3d back = rounds.current();
  ASSERT_TRUE(rounds.record(0.52, diagonal(0.2, 0.05, 0.002)));
  EXPECT_TRUE(rounds.current().isApprox(0.5 * (back + diagonal(0.2, 0.05, 0.002)), 1e-15));
}

// The trained Q itself too small: the first run ran away, its residuals asked for a huge Q, and the
// next run (stable under it) starts the rounds afresh.
TEST(ProcessNoiseRounds, StartsAfreshWhenTheFirstRoundRanAway) {
  ProcessNoiseRounds rounds(diagonal(1e-4, 1e-4, 1e-6));
  ASSERT_TRUE(rounds.record(200.0, diagonal(1e7, 1e5, 1e6)));
  EXPECT_EQ(rounds.current(), diagonal(1e7, 1e5, 1e6));
  EXPECT_TRUE(rounds.record(0.5, diagonal(0.2, 0.05, 0.002)));
  EXPECT_EQ(rounds.current(), diagonal(0.2, 0.05, 0.002));
  // The new reference is 0.5 m: 1.5 m now runs away, and Q steps back towards the huge one.
  EXPECT_FALSE(rounds.record(1.5, diagonal(0.1, 0.1, 0.1)));
  EXPECT_TRUE(rounds.current().isApprox(0.5 * (diagonal(1e7, 1e5, 1e6) + diagonal(0.2, 0.05, 0.002)), 1e-15));
}

TEST(ProcessNoiseRounds, TheCheckFallsBackToTheLastStableQ) {
  ProcessNoiseRounds rounds(diagonal(1.0, 1.0, 1.0));
  ASSERT_TRUE(rounds.record(0.5, diagonal(0.2, 0.2, 0.2)));
  ASSERT_TRUE(rounds.record(0.5, diagonal(0.02, 0.02, 0.02)));  // ran with 0.2: stable
  EXPECT_TRUE(rounds.current().isApprox(diagonal(0.11, 0.11, 0.11), 1e-15)) << rounds.current();
  EXPECT_FALSE(rounds.check(1.5));  // ran away with 0.11
  EXPECT_EQ(rounds.current(), diagonal(0.2, 0.2, 0.2));
}

TEST(ProcessNoiseRounds, NotFiniteIsRunningAway) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double infinity = std::numeric_limits<double>::infinity();
  EXPECT_THROW(ProcessNoiseRounds(diagonal(1.0, 1.0, 1.0)).record(nan, diagonal(1.0, 1.0, 1.0)), std::runtime_error);
  EXPECT_THROW(ProcessNoiseRounds(diagonal(1.0, 1.0, 1.0)).record(infinity, diagonal(1.0, 1.0, 1.0)),
               std::runtime_error);
  ProcessNoiseRounds rounds(diagonal(1.0, 1.0, 1.0));
  ASSERT_TRUE(rounds.record(0.5, diagonal(0.5, 0.5, 0.5)));
  EXPECT_FALSE(rounds.record(nan, diagonal(nan, nan, nan)));
  EXPECT_TRUE(rounds.current().allFinite());
  EXPECT_TRUE(ran_away(nan, 1.0));
  EXPECT_TRUE(ran_away(2.0000001, 1.0));
  EXPECT_FALSE(ran_away(2.0, 1.0));
}

}  // namespace
}  // namespace stgf
