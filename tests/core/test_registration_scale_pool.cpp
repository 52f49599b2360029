// SPDX-License-Identifier: Apache-2.0
// The registration prior's scales pooled across scenes (core/registration_scale_pool.hpp): the argmax
// of the summed grids of the epochs before a scene's own, with each scene's grid shifted by the scales
// it ran with; nothing in the first epoch; scenes in list order only.

#include "stgf/core/registration_scale_pool.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace stgf {
namespace {

using Point = RegistrationScalePool::Point;

// A concave grid peaked at (scale, ratio), relative to the prior a scene ran with.
std::vector<double> peaked_at(int scale, int ratio) {
  std::vector<double> grid;
  for (int r = 0; r < RegistrationScalePool::kRatioIndices; ++r) {
    for (int k = 0; k < RegistrationScalePool::kScaleIndices; ++k) {
      grid.push_back(-0.01 * (k - scale) * (k - scale) - 0.1 * (r - ratio) * (r - ratio));
    }
  }
  return grid;
}

TEST(RegistrationScalePool, EstimatesFromTheEpochsBeforeAScenesOwn) {
  RegistrationScalePool pool;
  EXPECT_FALSE(pool.estimate_for(0).has_value());
  for (std::size_t scene = 0; scene < 16; ++scene) pool.add(scene, peaked_at(60, 10), Point{});
  EXPECT_FALSE(pool.estimate_for(15).has_value());  // its own epoch is not complete
  const std::optional<Point> second = pool.estimate_for(16);
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->scale, 60);
  EXPECT_EQ(second->ratio, 10);
  EXPECT_NEAR(second->scales().translation, 32.0, 1e-12);  // 2^(60/4 − 10)
  EXPECT_NEAR(second->scales().noise_ratio, 128.0, 1e-12);  // κ_t 2^(10 − 8)
  // Scenes that ran with those scales and whose own evidence peaks where they ran: the same absolute
  // peak, whatever grid they learned in.
  for (std::size_t scene = 16; scene < 40; ++scene) pool.add(scene, peaked_at(40, 8), *second);
  const std::optional<Point> third = pool.estimate_for(40);
  ASSERT_TRUE(third.has_value());
  EXPECT_EQ(third->scale, 60);
  EXPECT_EQ(third->ratio, 10);
  // The estimate for a scene of epoch 2 does not see the scenes of epoch 2 already added (32 … 39).
  RegistrationScalePool fewer;
  for (std::size_t scene = 0; scene < 16; ++scene) fewer.add(scene, peaked_at(60, 10), Point{});
  for (std::size_t scene = 16; scene < 32; ++scene) fewer.add(scene, peaked_at(40, 8), *second);
  for (std::size_t scene = 32; scene < 40; ++scene) fewer.add(scene, peaked_at(0, 0), *second);
  EXPECT_EQ(fewer.estimate_for(33)->scale, 60);
}

TEST(RegistrationScalePool, RefusesScenesOutOfOrderAndMalformedGrids) {
  RegistrationScalePool pool;
  pool.add(20, peaked_at(40, 8), Point{});
  EXPECT_THROW(pool.add(3, peaked_at(40, 8), Point{}), std::logic_error);
  EXPECT_THROW(pool.add(21, std::vector<double>(10, 0.0), Point{}), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
