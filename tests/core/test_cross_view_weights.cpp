// SPDX-License-Identifier: Apache-2.0
// Down-weighting a measurement that the other views at its time place far off (core/cross_view_weights.hpp).

#include <random>

#include <gtest/gtest.h>

#include "stgf/core/cross_view_weights.hpp"

namespace stgf {
namespace {

CrossViewWeights::Measurement at(const Vector3d& position, double noise_variance = 0.01, double offset_variance = 0.0) {
  return {position, noise_variance * Matrix3d::Identity(), offset_variance * Matrix3d::Identity()};
}

TEST(CrossViewWeights, ScalesTheGrossErrorAloneToTheThreshold) {
  // σ = 0.1 m; the first is 5 m off.
  const std::vector<CrossViewWeights::Measurement> rows{at({5.0, 0.0, 0.0}), at({0.0, 0.0, 0.0}),
                                                       at({0.05, 0.0, 0.0}), at({-0.05, 0.0, 0.0})};
  const std::vector<double> scales = CrossViewWeights::noise_scales(rows);
  EXPECT_EQ(scales[1], 1.0);
  EXPECT_EQ(scales[2], 1.0);
  EXPECT_EQ(scales[3], 1.0);
  // Its disagreement with the others' mean (0, variance 0.01 / 3) at s: 25 / (0.01 s + 0.01 / 3) = γ.
  const double expected = (25.0 / CrossViewWeights::threshold() - 0.01 / 3.0) / 0.01;
  EXPECT_NEAR(scales[0], expected, 1e-6 * expected);
  EXPECT_GT(scales[0], 100.0);
}

TEST(CrossViewWeights, KeepsAgreeingMeasurementsAndPairsAsStated) {
  std::mt19937 random(1);
  std::normal_distribution<double> noise(0.0, 0.1);
  // Honest measurements rarely pass γ (one in a thousand, each): of 200 objects × 4 views, few are scaled, and
  // each by a little.
  std::size_t scaled = 0;
  for (int object = 0; object < 200; ++object) {
    std::vector<CrossViewWeights::Measurement> rows;
    for (int view = 0; view < 4; ++view) rows.push_back(at({noise(random), noise(random), noise(random)}));
    for (const double scale : CrossViewWeights::noise_scales(rows)) {
      EXPECT_GE(scale, 1.0);
      EXPECT_LT(scale, 3.0);
      scaled += scale > 1.0;
    }
  }
  EXPECT_LE(scaled, 5u);
  // Two that disagree cannot say which is wrong.
  const std::vector<CrossViewWeights::Measurement> two{at({5.0, 0.0, 0.0}), at({0.0, 0.0, 0.0})};
  EXPECT_EQ(CrossViewWeights::noise_scales(two), (std::vector<double>{1.0, 1.0}));
}

TEST(CrossViewWeights, CountsTheOffsetsUncertaintyBeforeCallingADisagreementGross) {
  // 1 m apart with 0.1 m noise, but each view's offset is uncertain by 1 m: nothing to down-weight.
  const std::vector<CrossViewWeights::Measurement> rows{at({1.0, 0.0, 0.0}, 0.01, 1.0), at({0.0, 0.0, 0.0}, 0.01, 1.0),
                                                       at({0.0, 0.0, 0.0}, 0.01, 1.0)};
  EXPECT_EQ(CrossViewWeights::noise_scales(rows), (std::vector<double>(3, 1.0)));
  // Without that uncertainty the far one is scaled.
  const std::vector<CrossViewWeights::Measurement> known{at({1.0, 0.0, 0.0}), at({0.0, 0.0, 0.0}), at({0.0, 0.0, 0.0})};
  const std::vector<double> scales = CrossViewWeights::noise_scales(known);
  EXPECT_GT(scales[0], 1.0);
  EXPECT_EQ(scales[1], 1.0);
  EXPECT_EQ(scales[2], 1.0);
}

TEST(CrossViewWeights, LeavesTwoAsStatedWhenTwoOfFourAreOff) {
  // Two gross errors in different directions among four: both scaled, the two that agree kept.
  const std::vector<CrossViewWeights::Measurement> rows{at({0.0, 0.0, 0.0}), at({4.0, 0.0, 0.0}),
                                                       at({0.02, 0.0, 0.0}), at({0.0, -6.0, 0.0})};
  const std::vector<double> scales = CrossViewWeights::noise_scales(rows);
  EXPECT_EQ(scales[0], 1.0);
  EXPECT_GT(scales[1], 10.0);
  EXPECT_EQ(scales[2], 1.0);
  EXPECT_GT(scales[3], 10.0);
}

}  // namespace
}  // namespace stgf
