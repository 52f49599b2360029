// SPDX-License-Identifier: Apache-2.0
// Writes a motion model file (untrained weights, seed 1), loads it back as a user would load one
// from `stgf train`, and streams two views' measurements of a walking object through the filter.
// Usage: filter_consumer MODEL_PATH
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include "stgf/learn/motion_model.hpp"
#include "stgf/methods/spatiotemporal_graph_filter.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  try {
    stgf::MotionModel(stgf::MotionModelShape{}, stgf::MotionNormalisation{}, 1).save(argv[1]);
    const stgf::MotionModel model = stgf::MotionModel::load(argv[1]);
    stgf::SpatiotemporalGraphFilter filter(model, stgf::FilterOptions{});
    const stgf::Matrix3d noise = 0.01 * stgf::Matrix3d::Identity();
    // Exact measurements with 10 cm noise each: whatever an untrained Φ predicts, the estimate stays
    // within a few centimetres and its covariance below a single view's.
    double worst = 0.0;
    double largest_variance = 0.0;
    for (int k = 0; k < 10; ++k) {
      const double t = 0.1 * k;
      const stgf::Vector3d truth(t, 0.0, 0.0);  // 1 m/s along x
      const std::vector<stgf::Measurement> step = {
          {"s", t, "a", "walker", stgf::Gaussian3::from_covariance(truth, noise), std::nullopt},
          {"s", t, "b", "walker", stgf::Gaussian3::from_covariance(truth, noise), std::nullopt}};
      std::vector<const stgf::Measurement*> rows = {&step[0], &step[1]};
      for (const stgf::Gaussian3& estimate : filter.step(t, rows)) {
        worst = std::max(worst, (estimate.mean() - truth).norm());
        largest_variance = std::max(largest_variance, estimate.covariance().diagonal().maxCoeff());
      }
    }
    std::printf("largest error %.4f m, largest variance %.4f m²\n", worst, largest_variance);
    return std::isfinite(worst) && worst < 0.05 && largest_variance < 0.01 ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "filter_consumer: %s\n", error.what());
    return 2;
  }
}
