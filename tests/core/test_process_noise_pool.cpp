// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/process_noise_pool.hpp"

#include <stdexcept>

#include <gtest/gtest.h>

#include "stgf/core/scene_epochs.hpp"

namespace stgf {
namespace {

// A scene's evidence: `value` at one grid point of each of its three scales.
ProcessNoiseEvidence evidence_of(double value) {
  ProcessNoiseEvidence evidence;
  evidence.followed[0][4] = value;
  evidence.fallback[1][5] = value;
  evidence.coasting[2][6] = value;
  return evidence;
}

TEST(SceneEpochs, DoubleUpToSixteenScenesThenStay) {
  const std::size_t starts[] = {0, 1, 2, 4, 8, 16, 32, 48, 64};
  for (std::size_t epoch = 0; epoch + 1 < std::size(starts); ++epoch) {
    for (std::size_t scene = starts[epoch]; scene < starts[epoch + 1]; ++scene) {
      EXPECT_EQ(scene_epoch(scene), epoch) << scene;
      EXPECT_EQ(scene_epoch_end(scene), starts[epoch + 1]) << scene;
    }
  }
}

TEST(ProcessNoisePool, ScenesStartFromTheEpochsBeforeTheirOwn) {
  ProcessNoisePool pool;
  EXPECT_FALSE(pool.evidence_for(0).has_value());
  pool.add(0, evidence_of(1.0));
  EXPECT_FALSE(pool.evidence_for(0).has_value());  // its own epoch
  ASSERT_TRUE(pool.evidence_for(1).has_value());
  EXPECT_EQ(pool.evidence_for(1)->followed[0][4], 1.0);
  pool.add(1, evidence_of(2.0));
  pool.add(2, evidence_of(4.0));
  // Scene 3 is in scene 2's epoch [2, 4): it starts from scenes 0 and 1 only.
  const std::optional<ProcessNoiseEvidence> third = pool.evidence_for(3);
  ASSERT_TRUE(third.has_value());
  EXPECT_EQ(third->followed[0][4], 3.0);
  EXPECT_EQ(third->fallback[1][5], 3.0);
  EXPECT_EQ(third->coasting[2][6], 3.0);
  EXPECT_EQ(third->followed[0][5], 0.0);
  pool.add(3, evidence_of(8.0));
  EXPECT_EQ(pool.evidence_for(4)->followed[0][4], 15.0);
  EXPECT_THROW(pool.add(1, evidence_of(1.0)), std::logic_error);
}

// What the run's scenes said of each scale: none for a scale no innovation taught.
TEST(ProcessNoisePool, ReportsTheScalesTheScenesTaught) {
  ProcessNoisePool pool;
  EXPECT_FALSE(pool.scales().followed.has_value());
  ProcessNoiseEvidence coasting_only;
  // log₂ λ = 2 (grid point kUnitPoint + 4) far the likeliest on every axis.
  for (auto& axis : coasting_only.coasting) axis[ProcessNoiseScale::kUnitPoint + 4] = 100.0;
  pool.add(0, coasting_only);
  const ProcessNoisePool::Scales scales = pool.scales();
  EXPECT_FALSE(scales.followed.has_value());
  EXPECT_FALSE(scales.fallback.has_value());
  ASSERT_TRUE(scales.coasting.has_value());
  EXPECT_EQ(*scales.coasting, Vector3d::Constant(4.0));
  // Held at 1 and above, as the scenes of a pool that may not fall below their calibration were.
  ProcessNoisePool held(/*below_one=*/false);
  EXPECT_TRUE(pool.below_one());
  EXPECT_FALSE(held.below_one());
  held.add(0, coasting_only);
  ProcessNoiseEvidence smaller;
  for (auto& axis : smaller.followed) axis[ProcessNoiseScale::kUnitPoint - 4] = 100.0;  // λ = 1/4
  pool.add(1, smaller);
  held.add(1, smaller);
  EXPECT_EQ(*pool.scales().followed, Vector3d::Constant(0.25));
  EXPECT_EQ(*held.scales().followed, Vector3d::Ones());
  EXPECT_EQ(*held.scales().coasting, Vector3d::Constant(4.0));
}

}  // namespace
}  // namespace stgf
