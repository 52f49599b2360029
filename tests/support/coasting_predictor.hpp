// SPDX-License-Identifier: Apache-2.0
#pragma once
// A constant-velocity predictor whose tracks coast beyond its horizon (core/motion_predictor.hpp), as
// a model with Q calibrated at longer intervals does.

#include <span>
#include <vector>

#include "stgf/core/motion_predictor.hpp"

namespace stgf::testing {

// Coasts from `horizon` up to `coasting_horizon`; q = 1 m²/s², typical speed 1 m/s.
class CoastingPredictor final : public MotionPredictor {
 public:
  CoastingPredictor(double horizon, double coasting_horizon)
      : base_(1.0, 1.0, horizon), coasting_horizon_(coasting_horizon) {}
  std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const override {
    return base_.forecast(graphs);
  }
  Matrix3d process_noise(double dt) const override { return base_.process_noise(dt); }
  int history_positions() const override { return base_.history_positions(); }
  double history_spacing() const override { return base_.history_spacing(); }
  double typical_speed() const override { return base_.typical_speed(); }
  double prediction_horizon() const override { return base_.prediction_horizon(); }
  double coasting_horizon() const override { return coasting_horizon_; }

 private:
  ConstantVelocityPredictor base_;
  double coasting_horizon_;
};

}  // namespace stgf::testing
