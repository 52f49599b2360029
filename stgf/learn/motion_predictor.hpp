#pragma once
// What the spatiotemporal graph filter needs from a motion model (DESIGN §1.1–1.2): a prediction
// of every object of a batch of graphs at the graph's target time, and the process noise Q(Δt)
// that goes with it. The learned Φ (MotionModel) is one; a constant-velocity predictor is another
// (a baseline, and the reference case in which the filter reduces to a Kalman filter).

#include <limits>
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
  // The longest interval (s) the predictor is trusted to predict across. An object that has not been
  // seen for longer starts a new track: a learned model extrapolated far beyond the intervals it
  // trained on is not a prediction (a pedestrian model asked for 4 s ahead can be off by tens of
  // metres while its Q, fitted at a fraction of a second, says centimetres).
  virtual double prediction_horizon() const = 0;
};

// x̂ = p_last + v_last Δt, v_last from the last two positions (zero with one position), and
// Q(Δt) = q Δt² I with q = `process_noise_per_second2` (m²/s²): an acceleration-driven spread.
// Its horizon is unlimited unless given (a track's maximum age).
class ConstantVelocityPredictor final : public MotionPredictor {
 public:
  ConstantVelocityPredictor(double process_noise_per_second2, double typical_speed,
                            double horizon = std::numeric_limits<double>::infinity())
      : process_noise_per_second2_(process_noise_per_second2), typical_speed_(typical_speed), horizon_(horizon) {}
  std::vector<std::vector<Vector3d>> predict(std::span<const MotionGraph> graphs) const override;
  Matrix3d process_noise(double dt) const override {
    return process_noise_per_second2_ * dt * dt * Matrix3d::Identity();
  }
  int history_positions() const override { return 2; }
  double typical_speed() const override { return typical_speed_; }
  double prediction_horizon() const override { return horizon_; }

 private:
  double process_noise_per_second2_;
  double typical_speed_;
  double horizon_;
};

}  // namespace stgf
