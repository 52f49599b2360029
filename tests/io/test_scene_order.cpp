// SPDX-License-Identifier: Apache-2.0
// Files read scene by scene: the rows of each scene must be contiguous, and a scene that comes back
// is named at its line with the command that groups the file.

#include "stgf/io/scene_order.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace stgf {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

TEST(SceneOrder, ContiguousScenesInAnyOrderPass) {
  detail::SceneOrder order;
  EXPECT_TRUE(order.opens_scene("f.csv", 2, "b", 0));
  EXPECT_FALSE(order.opens_scene("f.csv", 3, "b", 2));
  EXPECT_TRUE(order.opens_scene("f.csv", 4, "a", 3));
  EXPECT_TRUE(order.opens_scene("f.csv", 5, "c", 4));
}

TEST(SceneOrder, ASceneThatComesBackIsAnErrorAtItsLine) {
  detail::SceneOrder order;
  order.opens_scene("f.csv", 2, "a", 0);
  order.opens_scene("f.csv", 5, "b", 4);
  try {
    order.opens_scene("f.csv", 9, "a", 8);
    FAIL() << "no error";
  } catch (const SceneOrderError& error) {
    EXPECT_EQ(error.line(), 9);
    EXPECT_THAT(error.what(), StartsWith("f.csv:9: scene 'a' appears again after other scenes (its rows ended at line 4)"));
    EXPECT_THAT(error.what(), HasSubstr("must be grouped by scene"));
    EXPECT_THAT(error.what(), HasSubstr(group_by_scene_command("f.csv")));
  }
}

TEST(SceneOrder, GroupingCommandKeepsTheHeaderAndEachScenesOrder) {
  EXPECT_EQ(group_by_scene_command("m.csv"),
            "(head -n 1 m.csv && tail -n +2 m.csv | LC_ALL=C sort -s -t, -k1,1) > grouped.csv");
}

}  // namespace
}  // namespace stgf
