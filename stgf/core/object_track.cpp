#include "stgf/core/object_track.hpp"

#include <cmath>
#include <stdexcept>

namespace stgf {
namespace {

// s² (τ² − τ_s²) I, the spread of an unknown velocity, while the history holds one position.
Matrix3d speed_spread(const MotionPredictor& predictor, std::size_t history_positions, double tau, double tau_state) {
  if (history_positions != 1) return Matrix3d::Zero();
  const double speed = predictor.typical_speed();
  return speed * speed * (tau * tau - tau_state * tau_state) * Matrix3d::Identity();
}

}  // namespace

TrackPrediction ObjectTrack::predict(double time, const MotionPredictor& predictor,
                                     const ProcessNoiseScale& scale) const {
  if (empty() || !forecast_) throw std::logic_error("ObjectTrack::predict needs a track with a forecast");
  const TrackPoint& state = *state_;
  if (!(time > state.time)) throw std::logic_error("ObjectTrack::predict: time must follow the track's state");
  const double history_time = history_.back().time;
  const double tau = time - history_time;
  const double tau_state = state.time - history_time;
  const Vector3d mean = state.estimate.mean() + forecast_->displacement(tau) - forecast_->displacement(tau_state);
  const Matrix3d process_noise =
      symmetrised(predictor.process_noise(tau) - (tau_state > 0.0 ? predictor.process_noise(tau_state) : Matrix3d::Zero()));
  const Matrix3d covariance = state.estimate.covariance() + scale.scaled(process_noise) +
                              speed_spread(predictor, history_.size(), tau, tau_state);
  return {Gaussian3::from_covariance(mean, covariance), state.estimate.covariance(), process_noise,
          std::sqrt(tau * tau - tau_state * tau_state), history_.size()};
}

std::pair<Vector3d, Matrix3d> ObjectTrack::displacement_since_history(double time, const MotionPredictor& predictor,
                                                                      const ProcessNoiseScale& scale) const {
  if (history_.empty()) return {Vector3d::Zero(), Matrix3d::Zero()};
  const double tau = time - history_.back().time;
  if (!(tau > 0.0)) return {Vector3d::Zero(), Matrix3d::Zero()};
  const Vector3d displacement = forecast_ ? forecast_->displacement(tau) : Vector3d::Zero();
  return {displacement, scale.scaled(predictor.process_noise(tau)) + speed_spread(predictor, history_.size(), tau, 0.0)};
}

void ObjectTrack::update(double time, const Gaussian3& estimate, const MotionPredictor& predictor) {
  state_ = TrackPoint{time, estimate};
  if (!history_.empty() && time - history_.back().time < predictor.history_spacing()) return;
  history_.push_back(TrackPoint{time, estimate});
  const auto limit = static_cast<std::size_t>(predictor.history_positions());
  while (history_.size() > limit) history_.pop_front();
  forecast_.reset();
}

}  // namespace stgf
