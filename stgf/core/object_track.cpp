// SPDX-License-Identifier: Apache-2.0
#include "stgf/core/object_track.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "stgf/core/eigenvalue_floor.hpp"

namespace stgf {
namespace {

// w_i = (t_i − t̄) / Σ_j (t_j − t̄)² of the least-squares slope through the positions a forecast reads:
// the whole history, or its last two. None (valid() false) with fewer than two.
class SlopeWeights {
 public:
  SlopeWeights(const std::deque<TrackPoint>& history, bool last_two)
      : history_(history), first_(last_two && history.size() >= 2 ? history.size() - 2 : 0) {
    if (history.size() < 2) return;
    for (std::size_t i = first_; i < history.size(); ++i) mean_time_ += history[i].time;
    mean_time_ /= static_cast<double>(history.size() - first_);
    for (std::size_t i = first_; i < history.size(); ++i) {
      spread_ += (history[i].time - mean_time_) * (history[i].time - mean_time_);
    }
  }
  bool valid() const { return spread_ > 0.0; }
  std::size_t first() const { return first_; }
  double operator()(std::size_t i) const { return (history_[i].time - mean_time_) / spread_; }

 private:
  const std::deque<TrackPoint>& history_;
  std::size_t first_;
  double mean_time_ = 0.0;
  double spread_ = 0.0;
};

// The slope's error over the positions it reads, v̂ = Σ_j w_j p_j, in one backward walk of the history:
//   V   = Var(v̂)     = Σ_j (w_j² P_j + w_j (B_j P_j + (B_j P_j)ᵀ)),  B_j = Σ_{i>j} w_i G_i ⋯ G_{j+1},
//   K_n = Cov(v̂, e_n) = Σ_j w_j P_j Π_jᵀ,                            Π_j = G_n ⋯ G_{j+1}  (Π_n = I),
// with C_ij = G_i ⋯ G_{j+1} P_j the correlation of two positions' errors; backwards, B_{n−1} = 0,
// B_j = (w_{j+1} I + B_{j+1}) G_{j+1} and Π_j = Π_{j+1} G_{j+1}. Zero with fewer than two positions.
struct SlopeError {
  Matrix3d variance = Matrix3d::Zero();             // V
  Matrix3d position_covariance = Matrix3d::Zero();  // K_n
};

SlopeError slope_error(const std::deque<TrackPoint>& history, bool last_two) {
  SlopeError error;
  const SlopeWeights weight(history, last_two);
  if (!weight.valid()) return error;
  const std::size_t n = history.size(), first = weight.first();
  Matrix3d later = Matrix3d::Zero();       // B_j
  Matrix3d carried = Matrix3d::Identity();  // Π_j
  for (std::size_t j = n; j-- > first;) {
    if (j + 1 < n) {
      later = (weight(j + 1) * Matrix3d::Identity() + later) * history[j + 1].carried;
      carried = carried * history[j + 1].carried;
    }
    const Matrix3d& p_j = history[j].estimate.covariance();
    const Matrix3d cross = weight(j) * later * p_j;
    error.variance += weight(j) * weight(j) * p_j + cross + cross.transpose();
    error.position_covariance += weight(j) * p_j * carried.transpose();
  }
  // V a covariance: the correlations follow the model only as far as each G does (an update that widened
  // its prior, as a conflict's spread does, has no such G).
  error.variance = nearest_covariance(error.variance);
  return error;
}

}  // namespace

Vector3d ObjectTrack::last_velocity() const {
  const std::size_t n = history_.size();
  if (n < 2) return Vector3d::Zero();
  const TrackPoint& last = history_[n - 1];
  const TrackPoint& before = history_[n - 2];
  return (last.estimate.mean() - before.estimate.mean()) / (last.time - before.time);
}

Matrix3d ObjectTrack::velocity_variance(bool last_two) const { return slope_error(history_, last_two).variance; }

Matrix3d ObjectTrack::velocity_position_covariance(bool last_two) const {
  return slope_error(history_, last_two).position_covariance;
}

Matrix3d ObjectTrack::velocity_error_to(double time, bool last_two) const {
  // The forecast carries the slope's error δv on as J δv: from the state at τ_s to τ the prediction's
  // error is e_s + ΔJ δv, ΔJ = J(τ) − J(τ_s), and its covariance P̂_s plus
  //     ΔJ V ΔJ + ΔJ K_s + K_sᵀ ΔJ,   V = Var(v̂),  K_s = Cov(δv, e_s) = (K_n + V J(τ_s)) G_sᵀ,
  // G_s the share of the last history position's error (and of the slope error the predictions since
  // added, J(τ_s) δv) that the state carries.
  const double origin = forecast_origin();
  const double tau = time - origin, tau_state = state_->time - origin;
  const bool carried_as_is = last_two || !forecast_;  // constant velocity's, from the last two positions
  const Vector3d to = carried_as_is ? Vector3d::Constant(tau) : Vector3d(forecast_->slope_response(tau));
  const Vector3d from =
      carried_as_is ? Vector3d::Constant(tau_state) : Vector3d(forecast_->slope_response(tau_state));
  const SlopeError slope = slope_error(history_, last_two);
  const Matrix3d& variance = slope.variance;
  const Matrix3d cross = (slope.position_covariance + variance * from.asDiagonal()) * state_->carried.transpose();
  const Matrix3d delta = (to - from).asDiagonal();
  const Matrix3d grown = symmetrised(delta * variance * delta + delta * cross + cross.transpose() * delta);
  return grown_within(state_->estimate.covariance(), grown);
}

double ObjectTrack::unseen_limit(const MotionPredictor& predictor, double scene_frame_interval) const {
  const double horizon = predictor.coasting_horizon();
  if (!(horizon > predictor.prediction_horizon())) return horizon;  // no coasting Q to cross a frame with
  const double interval = frame_interval().value_or(scene_frame_interval);
  return std::isfinite(interval) ? std::max(horizon, kFramesUnseen * interval) : horizon;
}

Vector3d ObjectTrack::displacement_to(double time, bool constant_velocity) const {
  const double state_time = state_->time;
  if (constant_velocity) return last_velocity() * (time - state_time);
  if (!forecast_) return Vector3d::Zero();
  const double origin = forecast_origin();
  return forecast_->displacement(time - origin) - forecast_->displacement(state_time - origin);
}

ObjectTrack::Motion ObjectTrack::motion_to(double time, const MotionPredictor& predictor,
                                           const ProcessNoiseScale& scale, bool constant_velocity,
                                           bool velocity_error) const {
  if (empty()) throw std::logic_error("ObjectTrack::motion_to needs a track that is not empty");
  const bool coasting = coasts_to(time, predictor);
  if (needs_forecast() && !coasting) throw std::logic_error("ObjectTrack::motion_to needs the forecast of the track's history");
  const double state_time = state_->time;
  if (!(time > state_time)) throw std::logic_error("ObjectTrack::motion_to: time must follow the track's state");
  const double origin = forecast_origin();
  const double tau = time - origin;
  const double tau_state = state_time - origin;
  Motion motion;
  motion.displacement = displacement_to(time, constant_velocity || coasting);
  const auto q = [&](double t) { return coasting ? predictor.coasting_process_noise(t) : predictor.process_noise(t); };
  motion.process_noise = symmetrised(q(tau) - (tau_state > 0.0 ? q(tau_state) : Matrix3d::Zero()));
  motion.covariance = scale.scaled(motion.process_noise);
  if (history_.size() <= 1) {  // no velocity yet: the unknown speed's spread
    const double speed = predictor.typical_speed();
    motion.covariance += speed * speed * (tau * tau - tau_state * tau_state) * Matrix3d::Identity();
  }
  if (velocity_error) motion.covariance += velocity_error_to(time, /*last_two=*/constant_velocity || coasting);
  motion.interval = tau - tau_state;
  return motion;
}

TrackPrediction ObjectTrack::predict(double time, const MotionPredictor& predictor, const ProcessNoiseScale& scale,
                                     bool constant_velocity, bool velocity_error) const {
  const Motion motion = motion_to(time, predictor, scale, constant_velocity, velocity_error);
  const Gaussian3& state = state_->estimate;
  return {Gaussian3::from_covariance(state.mean() + motion.displacement, state.covariance() + motion.covariance),
          state.covariance(), motion.process_noise, motion.interval, history_.size()};
}

void ObjectTrack::update(double time, const Gaussian3& estimate) {
  if (!state_) first_time_ = time;
  state_ = TrackPoint{time, estimate, Matrix3d::Zero()};
}

void ObjectTrack::update(double time, const Gaussian3& estimate, const Matrix3d& prior_covariance) {
  if (!state_) {
    update(time, estimate);
    return;
  }
  // G = P⁺ (P⁻)⁻¹ = ((P⁻)⁻¹ P⁺)ᵀ, both symmetric.
  const Eigen::LDLT<Matrix3d> prior(prior_covariance);
  const Matrix3d share = prior.info() == Eigen::Success && prior.isPositive()
                             ? Matrix3d(prior.solve(estimate.covariance()).transpose())
                             : Matrix3d::Zero();
  state_ = TrackPoint{time, estimate, share * state_->carried};
}

void ObjectTrack::close_frame(const MotionPredictor& predictor) {
  if (!frame_time_ || !state_) throw std::logic_error("ObjectTrack::close_frame: no open frame");
  history_.push_back(*state_);
  state_->carried = Matrix3d::Identity();  // the state is the last history position
  const auto limit = static_cast<std::size_t>(predictor.history_positions());
  while (history_.size() > limit) history_.pop_front();
  if (history_.size() >= 2) {
    double interval = std::numeric_limits<double>::infinity();
    for (std::size_t k = 1; k < history_.size(); ++k) interval = std::min(interval, history_[k].time - history_[k - 1].time);
    frame_interval_ = interval;
  }
  forecast_.reset();
  frame_time_.reset();
  frame_alignment_ = FrameAlignment();
}

}  // namespace stgf
