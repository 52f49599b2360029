// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/scene_epochs.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace stgf {
namespace {

// A sum that remembers which scenes went into it: bit s for scene s.
struct Scenes {
  unsigned bits = 0;
  void add(const Scenes& other) { bits |= other.bits; }
};

TEST(SceneEpochs, EpochsDoubleUpToSixteenScenesThenStay) {
  const std::size_t expected[] = {0, 1, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5};
  for (std::size_t scene = 0; scene < std::size(expected); ++scene) EXPECT_EQ(scene_epoch(scene), expected[scene]);
  EXPECT_EQ(scene_epoch(31), 5u);
  EXPECT_EQ(scene_epoch(32), 6u);
  EXPECT_EQ(scene_epoch_end(5), 8u);
  EXPECT_EQ(scene_epoch_end(40), 48u);
}

TEST(EpochSums, ASceneStartsFromTheEpochsBeforeItsOwn) {
  EpochSums<Scenes> sums;
  for (std::size_t scene = 0; scene < 8; ++scene) sums.add_scene(scene).bits |= 1u << scene;
  // Scenes 4..7 are epoch 3: scene 6 starts from scenes 0..3, scene 8 (epoch 4) from 0..7.
  EXPECT_EQ(sums.before(6).evidence.bits, 0x0fu);
  EXPECT_EQ(sums.before(6).scenes, 4u);
  EXPECT_EQ(sums.before(8).evidence.bits, 0xffu);
  EXPECT_EQ(sums.before(8).scenes, 8u);
  EXPECT_EQ(sums.before(4).scenes, 4u);
  EXPECT_EQ(sums.all().evidence.bits, 0xffu);
  // Once a later epoch has begun, the earlier ones are committed and still counted.
  sums.add_scene(8).bits |= 1u << 8;
  EXPECT_EQ(sums.before(9).evidence.bits, 0xffu);
  EXPECT_EQ(sums.before(16).evidence.bits, 0x1ffu);
  EXPECT_EQ(sums.all().scenes, 9u);
}

TEST(EpochSums, RefusesAnEarlierEpochOnceALaterOneBegan) {
  EpochSums<Scenes> sums;
  sums.add_scene(4);
  EXPECT_NO_THROW(sums.add_scene(5));  // the same epoch, in any order within it
  EXPECT_THROW(sums.add_scene(2), std::logic_error);
  EXPECT_THROW(sums.before(2), std::logic_error);  // what scene 2 started from is no longer kept
  EXPECT_EQ(sums.before(4).scenes, 0u);
}

}  // namespace
}  // namespace stgf
