// SPDX-License-Identifier: Apache-2.0
#pragma once
// Predictors for tests: a constant-velocity predictor (core/motion_predictor.hpp) to which a test
// adds one behaviour by overriding one method.

#include <span>
#include <vector>

#include "stgf/core/motion_predictor.hpp"

namespace stgf::testing {

// Forwards everything to ConstantVelocityPredictor(q, speed, horizon, history_spacing).
class ForwardingPredictor : public MotionPredictor {
 public:
  ForwardingPredictor(double q, double speed, double horizon, double history_spacing = 0.0)
      : inner_(q, speed, horizon, history_spacing) {}
  std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const override {
    return inner_.forecast(graphs);
  }
  Matrix3d process_noise(double dt) const override { return inner_.process_noise(dt); }
  int history_positions() const override { return inner_.history_positions(); }
  double history_spacing() const override { return inner_.history_spacing(); }
  double typical_speed() const override { return inner_.typical_speed(); }
  double prediction_horizon() const override { return inner_.prediction_horizon(); }

 private:
  ConstantVelocityPredictor inner_;
};

// Tracks coast from `horizon` up to `coasting_horizon`, as with a model whose Q was calibrated at
// longer intervals; q = 1 m²/s², typical speed 1 m/s.
class CoastingPredictor final : public ForwardingPredictor {
 public:
  CoastingPredictor(double horizon, double coasting_horizon)
      : ForwardingPredictor(1.0, 1.0, horizon), coasting_horizon_(coasting_horizon) {}
  double coasting_horizon() const override { return coasting_horizon_; }

 private:
  double coasting_horizon_;
};

}  // namespace stgf::testing
