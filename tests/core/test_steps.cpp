// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/steps.hpp"

#include <gtest/gtest.h>

namespace stgf {
namespace {

Measurement at(const std::string& scene, double time, const std::string& view) {
  return Measurement{scene, time, view, "o", Gaussian3::from_covariance(Vector3d::Zero(), Matrix3d::Identity()),
                     std::nullopt};
}

TEST(GroupIntoScenes, ScenesInFirstAppearanceOrderStepsInTimeOrder) {
  const std::vector<Measurement> rows = {at("b", 0.2, "v1"), at("a", 0.1, "v1"), at("b", 0.1, "v1"),
                                         at("b", 0.2 + 5e-7, "v2"), at("a", 0.0, "v2")};
  const std::vector<Scene> scenes = group_into_scenes(rows);
  ASSERT_EQ(scenes.size(), 2u);
  EXPECT_EQ(scenes[0].name, "b");
  ASSERT_EQ(scenes[0].steps.size(), 2u);
  EXPECT_DOUBLE_EQ(scenes[0].steps[0].time, 0.1);
  EXPECT_EQ(scenes[0].steps[0].rows, (std::vector<std::size_t>{2}));
  EXPECT_DOUBLE_EQ(scenes[0].steps[1].time, 0.2);
  EXPECT_EQ(scenes[0].steps[1].rows, (std::vector<std::size_t>{0, 3}));  // within 1e-6 s: one step
  EXPECT_EQ(scenes[1].name, "a");
  ASSERT_EQ(scenes[1].steps.size(), 2u);
  EXPECT_EQ(scenes[1].steps[0].rows, (std::vector<std::size_t>{4}));
}

TEST(GroupIntoScenes, TimesFartherThanToleranceAreSeparateSteps) {
  const std::vector<Measurement> rows = {at("s", 1.0, "v1"), at("s", 1.0 + 2e-6, "v2")};
  EXPECT_EQ(group_into_scenes(rows)[0].steps.size(), 2u);
}

}  // namespace
}  // namespace stgf
