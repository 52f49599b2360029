// SPDX-License-Identifier: Apache-2.0
#pragma once
// One track of the spatiotemporal graph filter: what it knows of one object (DESIGN §1), in
// continuous time, for measurements that come on any clock.
//
// A track holds
//   - its state: the latest fused estimate N(x̂_s, P̂_s) at time t_s, updated by every measurement of
//     the object at the measurement's own time;
//   - its history: states at t_1 < … < t_h (at most the predictor's history_positions()), what the
//     motion model reads (the feedback of Algorithm 1: fused positions, not raw measurements);
//   - the forecast f made from that history (motion_predictor.hpp), absent until computed and dropped
//     whenever the history changes;
//   - an open frame: since when (t_g) the track gathers measurements toward its next history position.
//     scene_filter.hpp closes a frame once a frame window has passed (the predictor's history spacing for one track per object; any later
//     time for per-view tracks), and the state at that moment — fused from every view that measured
//     the object within the frame — becomes the next history position. On synchronised views a frame
//     is one step, and the history is the fused estimate of every step, as in DESIGN §1. (A history
//     position taken right after a single view's measurement would carry that view's residual offset,
//     and the views' differing offsets would turn into velocity: 0.1 m over a 1/7 s frame is 0.7 m/s.)
//
// Prediction to t > t_s, along the forecast from the last history position t_h (from the track's
// first time while it has none), with τ = t − t_h and τ_s = t_s − t_h:
//     x = x̂_s + f(τ) − f(τ_s)
//     P = P̂_s + D [Q(τ) − Q(τ_s)] D + ΔJ V ΔJ + ΔJ K_s + K_sᵀ ΔJ  (+ s² (τ² − τ_s²) I while the history holds at most one position)
// The forecast's error grows with the time since its history position, as Q(τ); between two updates
// along one forecast it grows by Q(τ) − Q(τ_s), so a track updated by seven unsynchronised cameras in
// a frame period accumulates the same process noise over that period as a track updated once by
// seven synchronised ones (a plain Q(t − t_s) per update would add up to a seventh of it with
// Q ∝ Δt², and the filter would trust its prediction seven times too much; below the calibration
// interval Q grows linearly, so there the two agree: process_noise_curve.hpp). D = diag(√λ) is the
// online scale of Q (process_noise_scale.hpp); s is the predictor's typical speed (the unknown
// velocity of a short history). Q must grow with its interval; the slope's terms (below) may take
// variance away.
//
// Var(v̂): the velocity the forecast reads from the history carries the history positions' errors, and
// the forecast carries that velocity's error on in proportion to τ. Q, calibrated on forecasts whose
// histories were long and whose positions had settled, holds little of it; a track's first forecasts
// read a velocity from two or three positions fused before the views' offsets were known, and were
// trusted too much (mpl val with mpl's model, NEES of the fused estimate at a track's third time 3.45
// where its neighbours' were 2.9–3.0; of the prediction alone 4.6 where later ones are 1.9, on the proxy
// without calibration error). v̂ is taken as the least-squares slope of the positions the forecast
// reads (all of the history for Φ, whose velocity that estimates; the last two for constant velocity
// and a track that coasts), w_i = (t_i − t̄) / Σ_j (t_j − t̄)²:
//     Var(v̂) = Σ_i Σ_j w_i w_j C_ij,   C_ii = P̂_i,   C_ij = G_i G_{i−1} ⋯ G_{j+1} P̂_j  (i > j),  C_ji = C_ijᵀ.
// Successive positions' errors are correlated: each update starts from the prediction of the last, and
// a position is the one before moved by the motion and pulled toward the measurements, its error
// G e_{i−1} + (an error independent of the history before), where G = P⁺ (P⁻)⁻¹ is the share of the
// prior in the update's posterior (x̂⁺ = P⁺ (P⁻)⁻¹ x⁻ + P⁺ Hᵀ R⁻¹ z for any linear-Gaussian update),
// multiplied over the updates from one history position to the next (TrackPoint::carried). Counted
// independent (C_ij = 0 for i ≠ j), the slope's error was 36–44 % too small on a moving axis (errors
// that follow each other with G ≈ 0.3–0.6 are slow, and a slope weighs the slow ones most) and, once
// settled, 3.7 times too large on a nearly still one (G near I: the errors nearly equal, and they
// cancel in a slope since Σ_i w_i = 0): a Kalman filter on a random walk, test_object_track.cpp. The
// error the forecast's own displacement adds between positions (Φ reads the positions) is not followed
// into C: first order in the velocity's error. With a history of n equally spaced positions of independent errors,
// Var(v̂) = 12 σ² / (n (n² − 1) Δt²): 2 σ²/Δt² for two, 0.02 σ²/Δt² for eight.
//
// How the forecast carries the slope's error δv = v̂ − v on: f(τ) moves by J(τ) δv, J = τ I for
// constant velocity (a track that coasts, or follows constant velocity) and Φ's own response for Φ,
// J(τ) = diag(velocity_response τ + ½ acceleration_response τ²), measured by a second pass of Φ on its
// histories tilted (slope_response.hpp). And δv is not independent of the state's error: the last
// history position's error is part of both (w_n > 0), so from the state at τ_s the prediction's error
// e_s + ΔJ δv, ΔJ = J(τ) − J(τ_s), has the covariance P̂_s + ΔJ V ΔJ + ΔJ K_s + K_sᵀ ΔJ with V = Var(v̂) and
//     K_s = Cov(δv, e_s) = (K_n + V J(τ_s)) G_sᵀ,   K_n = Cov(δv, e_n) = Σ_j w_j P̂_j (G_n ⋯ G_{j+1})ᵀ,
// G_s = TrackPoint::carried of the state (the share of e_n, and of the slope error J(τ_s) δv that the
// predictions since added, that it carries on; I at a history position). Where Φ brings a height back
// toward its history's (J_z < 0 on a ground plane), the slope's error and the state's cancel, and the
// prediction is more certain than the state: the term is then negative, held by grown_within so that P
// keeps at least half of P̂_s's least variance (on the validation splits a quarter or three quarters
// moved NEES by at most 0.02). With J = τ and τ_s = 0 the term is τ² V + τ (K_n + K_nᵀ):
// before 2026-12-02 (second change) the filter counted τ² V alone, as if δv were independent of the
// state, and as if Φ carried every slope on as constant velocity does. Design §1.2 has the numbers.

#include <deque>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "stgf/core/frame_alignment.hpp"
#include "stgf/core/motion_predictor.hpp"
#include "stgf/core/process_noise_scale.hpp"
#include "stgf/core/records.hpp"

namespace stgf {

struct TrackPoint {
  double time;
  Gaussian3 estimate;
  // G: the share of the previous history position's error this one's carries (the product of P⁺ (P⁻)⁻¹
  // over the updates since; zero for an estimate that owes it nothing). Of the state: since the last
  // history position.
  Matrix3d carried = Matrix3d::Zero();
};

// A prediction of a track to a time, with its parts (for the Q adaptation and its calibration).
struct TrackPrediction {
  Gaussian3 prior;                 // N(x, P)
  Matrix3d state_covariance;       // P̂_s
  Matrix3d process_noise;          // Q(τ) − Q(τ_s), before the scale D (and without the speed term)
  double interval = 0.0;           // τ − τ_s: the time since the state
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

  // Beyond the predictor's horizon (more than prediction_horizon() since the state; up to its
  // coasting_horizon(), after which the filter starts the track again), or with a history spaced wider
  // than the predictor's widest_history_spacing(), a track *coasts*: it is predicted by constant
  // velocity with the predictor's coasting Q (design §1.9). It needs no forecast.
  bool coasts_to(double time, const MotionPredictor& predictor) const {
    if (empty()) return false;
    const std::size_t n = history_.size();
    return time - state_->time > predictor.prediction_horizon() ||
           (n >= 2 && history_[n - 1].time - history_[n - 2].time > predictor.widest_history_spacing());
  }
  // How long the track may go unseen before the filter starts it again: the predictor's
  // coasting_horizon(); for a predictor that coasts at all (coasting_horizon() beyond
  // prediction_horizon(): a model whose Q was calibrated at longer intervals), that or kFramesUnseen
  // times the track's frame interval, whichever is longer. The frame interval is the shortest
  // between its history positions; while it has fewer than two, `scene_frame_interval`, the shortest
  // between two consecutive times of its scene. So a track coasts across one missed frame (two frame
  // intervals unseen, and half a frame for jitter) at the data's own rate, whatever rate the
  // predictor was trained and calibrated at: at 2 frames/s with a model whose coasting Q was
  // calibrated to 0.4 s, a track unseen for 1 s coasts with Q extrapolated as τ³
  // (process_noise_curve.hpp) and scaled by the coasting λ its own innovations teach (design §1.2);
  // one seen at a single time so far keeps its position, with the unknown speed's spread. A
  // predictor without a coasting curve has only Q(τ) ∝ τ² from its training rate beyond its horizon,
  // which understates the error there (mpl at 1 Hz with such a model: NEES 3.87 coasting, 2.81
  // starting again; design §1.9), so its tracks start again as before.
  static constexpr double kFramesUnseen = 2.5;
  double unseen_limit(const MotionPredictor& predictor,
                      double scene_frame_interval = std::numeric_limits<double>::infinity()) const;
  // The shortest interval between two history positions; none with fewer than two.
  std::optional<double> frame_interval() const { return frame_interval_; }
  const std::optional<MotionForecast>& forecast() const { return forecast_; }
  void set_forecast(const MotionForecast& forecast) { forecast_ = forecast; }

  // The motion from the state to `time` (> state().time) as above: x − x̂_s and P − P̂_s, with the parts
  // of TrackPrediction. A track with a history needs its forecast. With `constant_velocity`, f is
  // instead the constant-velocity forecast of the same history, f(τ) = v τ with v from its last two
  // positions (zero with fewer), and Q the predictor's (motion_choice.hpp).
  struct Motion {
    Vector3d displacement;
    Matrix3d covariance;     // D [Q(τ) − Q(τ_s)] D + the slope's terms (+ the speed term)
    Matrix3d process_noise;  // Q(τ) − Q(τ_s)
    double interval;
  };
  // Without `velocity_error`, P leaves Var(v̂) out (as Q's calibration sees it: learn/filter_calibration.hpp).
  Motion motion_to(double time, const MotionPredictor& predictor, const ProcessNoiseScale& scale,
                   bool constant_velocity = false, bool velocity_error = true) const;
  // The prediction to `time`: the state moved by motion_to(time).
  TrackPrediction predict(double time, const MotionPredictor& predictor, const ProcessNoiseScale& scale,
                          bool constant_velocity = false, bool velocity_error = true) const;
  // x − x̂_s of motion_to(time, …, constant_velocity) alone.
  Vector3d displacement_to(double time, bool constant_velocity) const;
  // v of the constant-velocity forecast: (p_h − p_{h−1}) / (t_h − t_{h−1}), zero with fewer than two positions.
  Vector3d last_velocity() const;
  // Var(v̂) of the least-squares velocity of the history positions (of the last two with `last_two`),
  // with their errors' correlation as each carries the one before's; zero with fewer than two.
  Matrix3d velocity_variance(bool last_two) const;
  // Cov(v̂, e_n): the slope's error with the last history position's (of the last two with `last_two`).
  Matrix3d velocity_position_covariance(bool last_two) const;
  // ΔJ Var(v̂) ΔJ + ΔJ K_s + K_sᵀ ΔJ to `time` (> state().time): what motion_to adds for the slope's
  // error (above). Not for an empty track. It may take variance away (held by grown_within).
  Matrix3d velocity_error_to(double time, bool last_two) const;
  // Makes (time, estimate) the state, an estimate that owes nothing to the one before (a track's start).
  void update(double time, const Gaussian3& estimate);
  // Makes (time, estimate) the state, fused from a prior of covariance `prior_covariance` that followed
  // from the state before (its prediction, or the state itself refined): the state carries
  // P⁺ (P⁻)⁻¹ of that one's error on. On an empty track, as update(time, estimate).
  void update(double time, const Gaussian3& estimate, const Matrix3d& prior_covariance);

  // ── The open frame ──
  bool has_frame() const { return frame_time_.has_value(); }
  double frame_time() const { return *frame_time_; }
  void open_frame(double time) { frame_time_ = time; }
  // The state becomes a history position, the frame ends (with what it gathered) and the forecast is dropped.
  void close_frame(const MotionPredictor& predictor);
  // The frame's measurements fused alone at their time, along the track's predicted path
  // (frame_alignment.hpp): what they say of the views' offsets is read before the frame closes.
  FrameAlignment& frame_alignment() { return frame_alignment_; }
  const FrameAlignment& frame_alignment() const { return frame_alignment_; }

  // ── Gating (measurement_gate.hpp) ──
  // Consecutive times at which every measurement of the object failed the gate.
  int gated_events() const { return gated_events_; }
  void count_gated_event() { ++gated_events_; }
  void reset_gated_events() { gated_events_ = 0; }

  // A track started from measurements that conflict (measurement_gate.hpp) knows where the object is
  // only as a mixture of them: its estimate says so, but it is no start for a velocity. The filter
  // starts it again at the object's next time.
  bool started_in_conflict() const { return started_in_conflict_; }
  void mark_started_in_conflict() { started_in_conflict_ = true; }

  // Forgets everything: the object starts again as if never seen.
  void clear() { *this = ObjectTrack(); }

 private:
  // The time the forecast runs from: the last history position, else the track's first time.
  double forecast_origin() const { return history_.empty() ? first_time_ : history_.back().time; }

  std::optional<TrackPoint> state_;
  double first_time_ = 0.0;
  std::deque<TrackPoint> history_;  // oldest first
  std::optional<double> frame_interval_;  // of history_, kept when it changes
  std::optional<MotionForecast> forecast_;
  std::optional<double> frame_time_;
  FrameAlignment frame_alignment_;
  int gated_events_ = 0;
  bool started_in_conflict_ = false;
};

}  // namespace stgf
