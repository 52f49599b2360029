// SPDX-License-Identifier: Apache-2.0
// The registration prior's scales pooled across scenes (core/registration_scale_pool.hpp): the argmax
// of the summed grids of the epochs before a scene's own, with each scene's grid shifted by the scales
// it ran with, or those grids themselves as a scene's start; nothing in the first epoch; scenes in list
// order only.

#include "stgf/core/registration_scale_pool.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace stgf {
namespace {

using Point = RegistrationScalePool::Point;
constexpr int kUnit = RegistrationScalePool::kUnitRatio;  // ρ = 1

// A concave grid peaked at (scale, ratio), relative to the prior a scene ran with, δ's along- and
// across-ray rows at 36 and 44, and κ_v's row at `vertical`.
std::vector<double> peaked_at(int scale, int ratio, int vertical = 30) {
  std::vector<double> grid;
  for (int r = 0; r < RegistrationScalePool::kRatioIndices; ++r) {
    for (int k = 0; k < RegistrationScalePool::kScaleIndices; ++k) {
      grid.push_back(-0.01 * (k - scale) * (k - scale) - 0.1 * (r - ratio) * (r - ratio));
    }
  }
  for (const int peak : {36, 44, vertical}) {
    for (int k = 0; k < RegistrationScalePool::kScaleIndices; ++k) grid.push_back(-0.01 * (k - peak) * (k - peak));
  }
  return grid;
}

TEST(RegistrationScalePool, EstimatesFromTheEpochsBeforeAScenesOwn) {
  RegistrationScalePool pool;
  EXPECT_FALSE(pool.estimate_for(0).has_value());
  for (std::size_t scene = 0; scene < 16; ++scene) pool.add(scene, peaked_at(60, kUnit + 2), Point{});
  EXPECT_FALSE(pool.estimate_for(15).has_value());  // its own epoch is not complete
  const std::optional<Point> second = pool.estimate_for(16);
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->scale, 60);
  EXPECT_EQ(second->ratio, kUnit + 2);
  EXPECT_NEAR(second->scales().translation, 32.0, 1e-12);  // 2^(60/4 − 10)
  EXPECT_NEAR(second->scales().noise_ratio, 128.0, 1e-12);  // κ_t 2^2
  // Scenes that ran with those scales and whose own evidence peaks where they ran: the same absolute
  // peak, whatever grid they learned in.
  for (std::size_t scene = 16; scene < 40; ++scene) pool.add(scene, peaked_at(40, kUnit), *second);
  const std::optional<Point> third = pool.estimate_for(40);
  ASSERT_TRUE(third.has_value());
  EXPECT_EQ(third->scale, 60);
  EXPECT_EQ(third->ratio, kUnit + 2);
  // The estimate for a scene of epoch 2 does not see the scenes of epoch 2 already added (32 … 39).
  RegistrationScalePool fewer;
  for (std::size_t scene = 0; scene < 16; ++scene) fewer.add(scene, peaked_at(60, kUnit + 2), Point{});
  for (std::size_t scene = 16; scene < 32; ++scene) fewer.add(scene, peaked_at(40, kUnit), *second);
  for (std::size_t scene = 32; scene < 40; ++scene) fewer.add(scene, peaked_at(0, kUnit - 8), *second);
  EXPECT_EQ(fewer.estimate_for(33)->scale, 60);
}

// Used to lower only (`shrink-across-scenes` with a prior that has a range scale, whose ridge with δ
// along the rays the summed disagreements ride): a scale whose estimate is above the calibration's
// (κ = 1) stays at 1, one below it is taken to the estimate.
TEST(RegistrationScalePool, LowersEveryScaleOnlyWhenSoUsed) {
  const auto pooled = [](int scale, int ratio, int vertical = 30) {
    RegistrationScalePool pool(RegistrationScalePool::Use::kLowerOnly);
    for (std::size_t scene = 0; scene < 16; ++scene)
      pool.add(scene, peaked_at(scale, ratio, vertical), Point{});
    return *pool.estimate_for(16);
  };
  const auto expect_scales = [](Point point, double translation, double noise_ratio) {
    EXPECT_NEAR(point.scales().translation, translation, 1e-12 * translation);
    EXPECT_NEAR(point.scales().noise_ratio, noise_ratio, 1e-12 * noise_ratio);
  };
  expect_scales(pooled(60, kUnit), 1.0, 1.0);                              // κ_t = κ_n = 32: both stay at 1
  expect_scales(pooled(20, kUnit + 4), 1.0 / 32.0, 0.5);                   // both below 1: as estimated
  expect_scales(pooled(20, kUnit + 8), 1.0 / 32.0, 1.0);                   // κ_n = 8 → 1
  expect_scales(pooled(60, kUnit - 8), 1.0, 1.0 / 8.0);                    // κ_t = 32 → 1, κ_n = 1/8 kept
  expect_scales(pooled(22, kUnit + 8), std::exp2(-4.5), std::exp2(-0.5));  // κ_n = 2^3.5 → 1, rounded down
  expect_scales(pooled(62, kUnit - 8), 1.0, std::exp2(-3.0));  // κ_t = 2^5.5 → 1, κ_n = 2^-2.5 rounded down
  EXPECT_NEAR(pooled(40, kUnit, 20).scales().vertical, 1.0 / 32.0, 1e-12);
  EXPECT_NEAR(pooled(40, kUnit, 60).scales().vertical, 1.0, 1e-12);
  EXPECT_EQ(RegistrationScalePool(RegistrationScalePool::Use::kLowerOnly).use(),
            RegistrationScalePool::Use::kLowerOnly);
}

// Used with the translations lowered only (`shrink-across-scenes`, the default for a model of several
// benchmarks on fixed sensors): κ_t above the calibration's (κ = 1) stays at 1, below it is taken to the
// estimate; κ_n is the estimate's either way.
TEST(RegistrationScalePool, LowersOnlyTheTranslationsWhenSoUsed) {
  const auto pooled = [](int scale, int ratio) {
    RegistrationScalePool pool(RegistrationScalePool::Use::kTranslationLoweredOnly);
    for (std::size_t scene = 0; scene < 16; ++scene) pool.add(scene, peaked_at(scale, ratio), Point{});
    return *pool.estimate_for(16);
  };
  const auto expect_scales = [](Point point, double translation, double noise_ratio) {
    EXPECT_NEAR(point.scales().translation, translation, 1e-12 * translation);
    EXPECT_NEAR(point.scales().noise_ratio, noise_ratio, 1e-12 * noise_ratio);
  };
  expect_scales(pooled(60, kUnit), 1.0, 32.0);                 // κ_t = κ_n = 32: κ_t → 1, κ_n kept
  expect_scales(pooled(20, kUnit + 4), 1.0 / 32.0, 0.5);       // both below 1: as estimated
  expect_scales(pooled(20, kUnit + 8), 1.0 / 32.0, 8.0);       // κ_n = 8 kept
  expect_scales(pooled(60, kUnit - 8), 1.0, 1.0 / 8.0);        // κ_t = 32 → 1, κ_n = 1/8 kept
  expect_scales(pooled(62, kUnit - 8), 1.0, std::exp2(-3.0));  // κ_t = 2^5.5 → 1, κ_n = 2^-2.5 rounded down
  expect_scales(pooled(20, kUnit + 12), 1.0 / 32.0, 128.0);  // ρ = 2^12, the grid's end: κ_t 1/32, κ_n 128
  // The model trained without mpl on mpl's cameras wanted ρ of about 2^10 (design §1.7), beyond the
  // 2^8 the grid had before: its ratio's whole range is searched.
  EXPECT_EQ(pooled(20, kUnit + 10).ratio, kUnit + 10);
  EXPECT_EQ(pooled(20, kUnit - 11).ratio, kUnit - 11);
  // κ_v, on its own row: its argmax, either way (an offset in units of the noise); a flat row (no
  // vertical offsets in any scene) leaves it at 1.
  const auto vertical = [](int peak, bool flat = false) {
    RegistrationScalePool pool(RegistrationScalePool::Use::kTranslationLoweredOnly);
    for (std::size_t scene = 0; scene < 16; ++scene) {
      std::vector<double> grid = peaked_at(40, kUnit, peak);
      if (flat) std::fill(grid.end() - RegistrationScalePool::kScaleIndices, grid.end(), 0.0);
      pool.add(scene, grid, Point{});
    }
    return pool.estimate_for(16)->scales().vertical;
  };
  // δ along and across the rays follow κ_n in the estimate (set apart only by evidence).
  EXPECT_NEAR(pooled(20, kUnit + 4).scales().along, 0.5, 1e-12);
  EXPECT_NEAR(pooled(20, kUnit + 4).scales().across, 0.5, 1e-12);
  EXPECT_NEAR(pooled(60, kUnit).scales().across, 32.0, 1e-12);
  EXPECT_NEAR(vertical(20), 1.0 / 32.0, 1e-12);
  EXPECT_NEAR(vertical(60), 32.0, 1e-12);
  EXPECT_NEAR(vertical(20, /*flat=*/true), 1.0, 1e-12);
  // Scenes that ran with κ_v scaled are shifted back: their row peaks at the calibration's 2^-5 too.
  RegistrationScalePool shifted(RegistrationScalePool::Use::kTranslationLoweredOnly);
  for (std::size_t scene = 0; scene < 16; ++scene) shifted.add(scene, peaked_at(40, kUnit, 20), Point{});
  const Point lowered = *shifted.estimate_for(16);
  for (std::size_t scene = 16; scene < 40; ++scene) shifted.add(scene, peaked_at(40, kUnit, 40), lowered);
  EXPECT_NEAR(shifted.estimate_for(40)->scales().vertical, 1.0 / 32.0, 1e-12);
  EXPECT_EQ(RegistrationScalePool(RegistrationScalePool::Use::kTranslationLoweredOnly).use(),
            RegistrationScalePool::Use::kTranslationLoweredOnly);
  EXPECT_EQ(RegistrationScalePool().use(), RegistrationScalePool::Use::kEvidence);
}

// Use::kEvidence: a scene starts from the summed grids of the epochs before its own, as they are.
TEST(RegistrationScalePool, GivesTheEpochsBeforeAScenesOwnAsItsStart) {
  // As the filter runner asks: a scene's start, then its grid, in list order.
  RegistrationScalePool pool;
  EXPECT_FALSE(pool.evidence_for(0).has_value());
  pool.add(0, peaked_at(40, kUnit), Point{});
  const std::vector<double> first = *pool.evidence_for(1);  // scene 0's
  pool.add(1, peaked_at(41, kUnit, 20), Point{});
  pool.add(2, peaked_at(42, kUnit), Point{});
  const std::vector<double> both = *pool.evidence_for(3);  // scenes 0 and 1 ([2, 4) is one epoch)
  const std::vector<double> zero = peaked_at(40, kUnit), one = peaked_at(41, kUnit, 20);  // κ_v's rows too
  ASSERT_EQ(both.size(), zero.size());
  for (std::size_t j = 0; j < zero.size(); ++j) {
    EXPECT_EQ(first[j], zero[j]);
    EXPECT_EQ(both[j], zero[j] + one[j]);
  }
  // A scene that ran with the prior scaled cannot be a start on the calibration's grid.
  RegistrationScalePool shifted;
  shifted.add(0, peaked_at(40, kUnit), Point{44, kUnit});
  EXPECT_THROW(shifted.evidence_for(1), std::logic_error);
}

TEST(RegistrationScalePool, RefusesScenesOutOfOrderAndMalformedGrids) {
  RegistrationScalePool pool;
  pool.add(20, peaked_at(40, kUnit), Point{});
  EXPECT_THROW(pool.add(3, peaked_at(40, kUnit), Point{}), std::logic_error);
  EXPECT_THROW(pool.add(21, std::vector<double>(10, 0.0), Point{}), std::invalid_argument);
  EXPECT_THROW(pool.add(21, std::vector<double>(18 * 81, 0.0), Point{}), std::invalid_argument);  // no axes' rows
}

}  // namespace
}  // namespace stgf
