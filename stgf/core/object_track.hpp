#pragma once
// One track of the spatiotemporal graph filter: what it knows of one object (DESIGN §1), in
// continuous time.
//
// A track holds
//   - its state: the latest fused estimate N(x̂_s, P̂_s) at time t_s;
//   - its history: fused estimates at times t_1 < … < t_h (at most the predictor's
//     history_positions()), at least the predictor's history_spacing() apart — what the motion model
//     reads (the feedback of Algorithm 1: fused positions, not raw measurements);
//   - the forecast f made from that history (motion_predictor.hpp), absent until computed and
//     dropped whenever the history changes.
// An update at time t becomes the new state; it also becomes a new history position when the history
// is empty or t − t_h ≥ history_spacing(), else the history (and its forecast) stay as they are. On
// synchronous data at the model's rate every update is a history position, and t_s = t_h.
//
// Prediction to t > t_s. With τ = t − t_h, τ_s = t_s − t_h:
//     x = x̂_s + f(τ) − f(τ_s)
//     P = P̂_s + D [Q(τ) − Q(τ_s)] D  (+ s² (τ² − τ_s²) I while the history holds one position)
// The forecast's error grows with the time since its history position, as Q(τ); between two updates
// along the same forecast it grows by Q(τ) − Q(τ_s), so a track updated by seven unsynchronised
// cameras in one frame period accumulates the same process noise over that period, Q(period), as a
// track updated once by seven synchronised ones (a plain Q(t − t_s) per update would add up to a
// seventh of it with Q ∝ Δt², and the filter would trust its prediction seven times too much).
// D = diag(√λ) is the online scale of Q (process_noise_scale.hpp). With one history position there is
// no velocity (f = Φ's guess from a standing start, or 0), and the unknown speed s (the predictor's
// typical_speed()) adds its spread the same way. Q must grow with its interval, so P ⪰ P̂_s.

#include <deque>
#include <optional>

#include "stgf/core/motion_predictor.hpp"
#include "stgf/core/process_noise_scale.hpp"

namespace stgf {

struct TrackPoint {
  double time;
  Gaussian3 estimate;
};

// A prediction of a track to a time, with its parts (for the Q adaptation and its calibration).
struct TrackPrediction {
  Gaussian3 prior;                 // N(x, P)
  Matrix3d state_covariance;       // P̂_s
  Matrix3d process_noise;          // Q(τ) − Q(τ_s), before the scale D (and without the speed term)
  double interval = 0.0;           // √(τ² − τ_s²): the interval whose Q(Δt) ∝ Δt² equals that increment
  std::size_t history_positions = 0;
};

class ObjectTrack {
 public:
  bool empty() const { return !state_.has_value(); }
  // The latest estimate. Only for a track that is not empty.
  const TrackPoint& state() const { return *state_; }
  const std::deque<TrackPoint>& history() const { return history_; }

  // A forecast is needed before the next prediction: the history is not empty and has none.
  bool needs_forecast() const { return !history_.empty() && !forecast_.has_value(); }
  const std::optional<MotionForecast>& forecast() const { return forecast_; }
  void set_forecast(const MotionForecast& forecast) { forecast_ = forecast; }

  // The prediction to `time` (> state().time) as above. The track must have a forecast.
  TrackPrediction predict(double time, const MotionPredictor& predictor, const ProcessNoiseScale& scale) const;

  // Where the object was, relative to its last history position, `time` − t_h later along the
  // forecast (zero without one), and the covariance of that displacement's error, D Q(τ) D (plus the
  // speed term): for moving a measurement at `time` back to t_h.
  std::pair<Vector3d, Matrix3d> displacement_since_history(double time, const MotionPredictor& predictor,
                                                           const ProcessNoiseScale& scale) const;

  // Makes (time, estimate) the state, and a history position when it is due (see above).
  void update(double time, const Gaussian3& estimate, const MotionPredictor& predictor);

  // Forgets everything: the object starts again as if never seen.
  void clear() {
    state_.reset();
    history_.clear();
    forecast_.reset();
  }

 private:
  std::optional<TrackPoint> state_;
  std::deque<TrackPoint> history_;  // oldest first
  std::optional<MotionForecast> forecast_;
};

}  // namespace stgf
