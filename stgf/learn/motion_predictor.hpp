#pragma once
// What the spatiotemporal graph filter needs from a motion model (DESIGN §1.1–1.2): a prediction
// of every object of a batch of graphs at the graph's target time, and the process noise Q(Δt)
// that goes with it. The learned Φ (MotionModel) is one; a constant-velocity predictor is another
// (a baseline, and the reference case in which the filter reduces to a Kalman filter).

#include <span>
#include <vector>

#include "stgf/learn/motion_graph.hpp"

namespace stgf {

class MotionPredictor {
 public:
  virtual ~MotionPredictor() = default;
  // Predicted positions at each graph's target time, per graph and object, in order.
  virtual std::vector<std::vector<Vector3d>> predict(std::span<const MotionGraph> graphs) const = 0;
  // Q for a prediction interval of `dt` seconds.
  virtual Matrix3d process_noise(double dt) const = 0;
  // How many past positions a prediction looks at (H + 1 for H history intervals).
  virtual int history_positions() const = 0;
  // A typical speed (m/s): a history of a single position leaves the velocity unknown, and
  // (speed · Δt)² I is added to the prediction's covariance for it.
  virtual double typical_speed() const = 0;
};

// x̂ = p_last + v_last Δt, v_last from the last two positions (zero with one position), and
// Q(Δt) = q Δt² I with q = `process_noise_per_second2` (m²/s²): an acceleration-driven spread.
class ConstantVelocityPredictor final : public MotionPredictor {
 public:
  ConstantVelocityPredictor(double process_noise_per_second2, double typical_speed)
      : process_noise_per_second2_(process_noise_per_second2), typical_speed_(typical_speed) {}
  std::vector<std::vector<Vector3d>> predict(std::span<const MotionGraph> graphs) const override;
  Matrix3d process_noise(double dt) const override {
    return process_noise_per_second2_ * dt * dt * Matrix3d::Identity();
  }
  int history_positions() const override { return 2; }
  double typical_speed() const override { return typical_speed_; }

 private:
  double process_noise_per_second2_;
  double typical_speed_;
};

}  // namespace stgf
