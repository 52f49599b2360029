// SPDX-License-Identifier: Apache-2.0
#include "stgf/datasets/recording.hpp"

#include <set>

#include <gtest/gtest.h>

#include "stgf/datasets/gaussian_noise.hpp"

namespace stgf {
namespace {

Recording toy_recording() {
  // a: frames 0–9; b: frames 2–9; c: frames 0–4; frame 6 missing entirely for nobody (all present).
  Recording recording{"toy", 10.0, {}};
  for (int frame = 0; frame < 10; ++frame) {
    recording.frames[frame]["a"] = Vector3d(frame, 0, 0);
    if (frame >= 2) recording.frames[frame]["b"] = Vector3d(0, frame, 0);
    if (frame <= 4) recording.frames[frame]["c"] = Vector3d(0, 0, frame);
  }
  return recording;
}

TEST(Recording, WindowsKeepObjectsPresentThroughout) {
  const std::vector<Window> windows = windows_with_objects(toy_recording(), 0, 10, 3, 2);
  // Starts 0..7; two objects throughout: s=0 (a,c), s=1 (a,c), s=2 (a,b,c), s≥3 (a,b).
  ASSERT_EQ(windows.size(), 8u);
  EXPECT_EQ(windows[0].first_frame, 0);
  EXPECT_EQ(windows[0].present, (std::vector<std::string>{"a", "c"}));
  EXPECT_EQ(windows[2].present, (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(windows[7].present, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(windows_with_objects(toy_recording(), 0, 10, 3, 3).size(), 1u);
  EXPECT_TRUE(windows_with_objects(toy_recording(), 0, 10, 11, 1).empty());
  EXPECT_EQ(windows_with_objects(toy_recording(), 5, 8, 3, 1).size(), 1u);  // only [5, 8)
}

TEST(Recording, MissingFrameBreaksWindows) {
  Recording recording = toy_recording();
  recording.frames.erase(5);
  for (const Window& window : windows_with_objects(recording, 0, 10, 3, 1)) {
    EXPECT_TRUE(window.first_frame + 3 <= 5 || window.first_frame > 5) << window.first_frame;
  }
}

TEST(Recording, ChooseIdsIsAUniformSubsetInOrder) {
  const std::vector<std::string> ids = {"a", "b", "c", "d"};
  RandomStream random(1);
  std::map<std::string, int> counts;
  const int draws = 4000;
  for (int k = 0; k < draws; ++k) {
    const std::vector<std::string> chosen = choose_ids(random, ids, 2);
    ASSERT_EQ(chosen.size(), 2u);
    ASSERT_LT(chosen[0], chosen[1]);
    ++counts[chosen[0] + chosen[1]];
  }
  // Six pairs, each with probability 1/6: 5 standard errors of a binomial count.
  for (const auto& [pair, count] : counts) EXPECT_NEAR(count, draws / 6.0, 5 * std::sqrt(draws * (1.0 / 6) * (5.0 / 6)));
  EXPECT_EQ(counts.size(), 6u);
  EXPECT_THROW(choose_ids(random, ids, 5), std::invalid_argument);
}

// Errors drawn for a covariance have that covariance: sample covariance within a few standard errors.
TEST(GaussianNoise, DrawsHaveTheCovariance) {
  Matrix3d covariance;
  covariance << 0.5, 0.2, 0.05, 0.2, 0.3, -0.04, 0.05, -0.04, 0.1;
  RandomStream random(2);
  const int draws = 40000;
  Matrix3d sum = Matrix3d::Zero();
  for (int k = 0; k < draws; ++k) {
    const Vector3d error = draw_gaussian_error(random, covariance);
    sum += error * error.transpose();
  }
  const Matrix3d sample = sum / draws;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      // var of e_i e_j is Σii Σjj + Σij²
      const double standard_error = std::sqrt((covariance(i, i) * covariance(j, j) + covariance(i, j) * covariance(i, j)) / draws);
      EXPECT_NEAR(sample(i, j), covariance(i, j), 5 * standard_error) << i << "," << j;
    }
  }
  EXPECT_THROW(draw_gaussian_error(random, -Matrix3d::Identity()), std::invalid_argument);
}

}  // namespace
}  // namespace stgf
