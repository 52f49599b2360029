// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/sensor_motion.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace stgf {
namespace {

Measurement row(double time, const std::string& view, std::optional<Vector3d> sensor) {
  return Measurement{"s", time, view, "o", Gaussian3::from_covariance(Vector3d::Zero(), Matrix3d::Identity()), sensor,
                     std::nullopt};
}

SensorMotion of(const std::vector<Measurement>& rows) {
  const std::vector<Scene> scenes = group_into_scenes(rows);
  EXPECT_EQ(scenes.size(), 1u);
  return sensor_motion(rows, scenes.front());
}

TEST(SensorMotion, FixedViewsAtTheirOwnPlacesStandStill) {
  // Views far apart, each where it always is: the distance counted is a view's own.
  EXPECT_EQ(of({row(0.0, "a", Vector3d(0, 0, 5)), row(0.0, "b", Vector3d(40, 0, 5)), row(0.1, "a", Vector3d(0, 0, 5)),
                row(0.1, "b", Vector3d(40, 0, 5))}),
            SensorMotion::kFixed);
}

TEST(SensorMotion, AViewThatMovesMoreThanTheDistanceMovesTheScene) {
  const double d = kMovingSensorDistance;
  EXPECT_EQ(of({row(0.0, "a", Vector3d(0, 0, 0)), row(0.1, "b", Vector3d(9, 9, 0)), row(0.2, "a", Vector3d(0.9 * d, 0, 0))}),
            SensorMotion::kFixed);
  EXPECT_EQ(of({row(0.0, "a", Vector3d(0, 0, 0)), row(0.1, "b", Vector3d(9, 9, 0)), row(0.2, "a", Vector3d(0, 1.1 * d, 0))}),
            SensorMotion::kMoving);
}

TEST(SensorMotion, RowsWithoutASensorPositionCountAsFixed) {
  EXPECT_EQ(of({row(0.0, "a", std::nullopt), row(0.1, "a", std::nullopt)}), SensorMotion::kFixed);
  EXPECT_EQ(of({row(0.0, "a", std::nullopt), row(0.1, "a", Vector3d(0, 0, 0)), row(0.2, "a", std::nullopt)}),
            SensorMotion::kFixed);
}

// Row by row (a streaming filter's scene): fixed until a view has moved, moving from then on.
TEST(SensorMotion, TheWatchSeesTheSceneMoveWhenAViewHasMoved) {
  const double d = kMovingSensorDistance;
  SensorMotionWatch watch;
  EXPECT_EQ(watch.motion(), SensorMotion::kFixed);
  watch.see(row(0.0, "a", Vector3d(0, 0, 0)));
  watch.see(row(0.0, "b", Vector3d(9, 9, 0)));
  watch.see(row(0.1, "a", std::nullopt));
  watch.see(row(0.1, "a", Vector3d(0.9 * d, 0, 0)));
  EXPECT_EQ(watch.motion(), SensorMotion::kFixed);
  watch.see(row(0.2, "b", Vector3d(9, 9 + 1.1 * d, 0)));
  EXPECT_EQ(watch.motion(), SensorMotion::kMoving);
  watch.see(row(0.3, "b", Vector3d(9, 9, 0)));  // back where it was: the scene's sensors have moved all the same
  EXPECT_EQ(watch.motion(), SensorMotion::kMoving);
}

TEST(SensorMotion, PerSensorMotionHoldsOneOfEach) {
  PerSensorMotion<int> counts;
  ++counts[SensorMotion::kMoving];
  counts[SensorMotion::kFixed] += 2;
  EXPECT_EQ(counts.fixed, 2);
  EXPECT_EQ(counts.moving, 1);
}

}  // namespace
}  // namespace stgf
