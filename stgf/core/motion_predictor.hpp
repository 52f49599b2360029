// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the spatiotemporal graph filter needs from a motion model (DESIGN §1.1–1.2), without LibTorch:
// for each object of a batch of graphs, a forecast of its motion after its last history position,
// closed-form in the time ahead, and the process noise Q(Δt) that goes with it. The learned Φ
// (learn/motion_model.hpp) is one; a constant-velocity predictor is another (a baseline, and the
// reference case in which the filter reduces to a Kalman filter).
//
// A forecast is a displacement polynomial in τ, the time since the last history position:
//     f(τ) = v τ + ½ a τ²,        x̂(t_last + τ) = p_last + f(τ).
// Φ's prediction has exactly this form (its decoder reads the history, not the time ahead; see
// motion_model.hpp), so one forecast serves every time at which the object is measured next, from
// any view and on any clock: the network runs once per new history position, not once per timestamp.

#include <limits>
#include <span>
#include <vector>

#include "stgf/core/motion_graph.hpp"

namespace stgf {

struct MotionForecast {
  Vector3d velocity = Vector3d::Zero();      // v (m/s): at the last history position
  Vector3d acceleration = Vector3d::Zero();  // a (m/s²)
  // f(τ) = v τ + ½ a τ²: where the object is τ seconds after its last history position, relative to it.
  Vector3d displacement(double tau) const { return velocity * tau + 0.5 * tau * tau * acceleration; }
  // How f responds to the history's slope, per axis (slope_response.hpp): a slope error δ (m/s) on
  // axis a moves f(τ)_a by J_a(τ) δ, J(τ) = velocity_response τ + ½ acceleration_response τ². As
  // constant velocity's forecast does, by default: J = τ.
  Vector3d velocity_response = Vector3d::Ones();
  Vector3d acceleration_response = Vector3d::Zero();
  Vector3d slope_response(double tau) const {
    return velocity_response * tau + 0.5 * tau * tau * acceleration_response;
  }
};

class MotionPredictor {
 public:
  virtual ~MotionPredictor() = default;
  // The forecast of every object of each graph, per graph and object, in order. A graph's target
  // time plays no part in it.
  virtual std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const = 0;
  // Predicted positions at each graph's target time, per graph and object, in order:
  // p_last + f(target_time − t_last). A predictor may compute it more directly.
  virtual std::vector<std::vector<Vector3d>> predict(std::span<const MotionGraph> graphs) const;
  // Q for a prediction interval of `dt` seconds: the covariance of f(dt)'s error. It must grow with dt.
  virtual Matrix3d process_noise(double dt) const = 0;
  // How many past positions a forecast looks at (H + 1 for H history intervals).
  virtual int history_positions() const = 0;
  // The shortest interval between two history positions a forecast is made from. Measurements closer
  // than this to a track's last history position refine its estimate without starting a new history
  // position (a learned model reads velocities over the intervals it trained on, not over the few
  // milliseconds between two cameras' frames, which would make them mostly noise).
  virtual double history_spacing() const = 0;
  // A typical speed (m/s): a history of a single position leaves the velocity unknown, and
  // (speed · τ)² I is added to the prediction's covariance for it.
  virtual double typical_speed() const = 0;
  // The longest interval (s) the predictor is trusted to predict across. An object that has not been
  // seen for longer starts a new track: a learned model extrapolated far beyond the intervals it
  // trained on is not a prediction (a pedestrian model asked for 4 s ahead can be off by tens of
  // metres while its Q, fitted at a fraction of a second, says centimetres).
  virtual double prediction_horizon() const = 0;
  // How long a track may go unseen before it starts again. Beyond prediction_horizon() and up to this,
  // the track *coasts*: it is predicted by constant velocity from its history with
  // coasting_process_noise(τ), calibrated for what constant velocity does over such intervals
  // (process_noise_curve.hpp). By default no track coasts.
  virtual double coasting_horizon() const { return prediction_horizon(); }
  // A track whose last two history positions are further apart than this coasts too: its history is
  // spaced wider than any the predictor learnt from (a lower frame rate than its training data's).
  // Infinite by default.
  virtual double widest_history_spacing() const { return std::numeric_limits<double>::infinity(); }
  // Q(Δt) of a coasting track's constant-velocity forecast.
  virtual Matrix3d coasting_process_noise(double dt) const { return process_noise(dt); }
};

// v = (p_n − p_{n−1}) / (t_n − t_{n−1}) from the last two positions (zero with one position), a = 0,
// and Q(Δt) = q Δt² I with q = `process_noise_per_second2` (m²/s²): an acceleration-driven spread.
// Its horizon is unlimited unless given (a track's maximum age); its history spacing is 0 unless given.
class ConstantVelocityPredictor final : public MotionPredictor {
 public:
  ConstantVelocityPredictor(double process_noise_per_second2, double typical_speed,
                            double horizon = std::numeric_limits<double>::infinity(), double history_spacing = 0.0)
      : process_noise_per_second2_(process_noise_per_second2),
        typical_speed_(typical_speed),
        horizon_(horizon),
        history_spacing_(history_spacing) {}
  std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const override;
  Matrix3d process_noise(double dt) const override {
    return process_noise_per_second2_ * dt * dt * Matrix3d::Identity();
  }
  int history_positions() const override { return 2; }
  double history_spacing() const override { return history_spacing_; }
  double typical_speed() const override { return typical_speed_; }
  double prediction_horizon() const override { return horizon_; }

 private:
  double process_noise_per_second2_;
  double typical_speed_;
  double horizon_;
  double history_spacing_;
};

}  // namespace stgf
