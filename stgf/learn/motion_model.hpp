// SPDX-License-Identifier: Apache-2.0
#pragma once
// The learned motion model Φ of the spatiotemporal graph filter (DESIGN §1.1–1.2), behind an
// interface that keeps LibTorch out of every public header.
//
// For each object of a MotionGraph, Φ predicts where it will be at the graph's target time:
//
//   input     per history interval k: velocity v_k = (p_k − p_{k−1}) / Δt_k (m/s), acceleration
//             a_k = (v_k − v_{k−1}) / ((t_k − t_{k−2}) / 2) (m/s²) and a flag saying whether the
//             interval exists (short histories are padded at the start) — per-second quantities only,
//             no step periods, so the network does not learn the training data's sampling rate;
//             per object: its last position (for relative positions between neighbours) and the
//             time to predict ahead, Δt = target_time − t_last (used only in the output below).
//   encoder   Linear(7→16) + ReLU, then an LSTM (hidden 32) over the H intervals: motion embedding m_i.
//   spatial   two graph-attention layers over the objects of the graph (edges: all pairs for graphs
//             of up to `max_fully_connected` objects, else each object's k nearest, plus self-loops):
//               message_ji = W h_j + U (p_j − p_i) / s_p
//               score_ji   = LeakyReLU(a_selfᵀ W h_i + a_msgᵀ message_ji)
//               α_ji       = softmax over the neighbours j of i of score_ji     (paper Eqs. 7–8)
//               h'_i       = ELU(Σ_j α_ji message_ji)
//             sizes 32→16 and 16→32 (the paper's 16×16 and 16×32 do not fit m of size 32): s_i.
//   decoder   an LSTM cell (hidden 32) started from the encoder's state, fed with m_i ‖ s_i ‖ v_last,
//             whose output maps (Linear 32→3) to an acceleration â (in units of s_v / s_t):
//               v̂ = v_last + â (Δt_last + Δt) / 2,     x̂ = p_last + v̂ Δt
//             v_last, measured over the last interval Δt_last, lags the current velocity by half
//             that interval, and the velocity keeps changing over the Δt ahead; writing the
//             correction as an acceleration times that time span makes Φ independent of the
//             sampling rate (a model trained at 2.5 Hz predicts at 5 Hz or 1.25 Hz, tested), and an
//             untrained Φ (small head) is close to the constant-velocity model.
//             Nothing before the output depends on Δt, so one pass gives the forecast for every Δt:
//               f(Δt) = (v_last + â Δt_last / 2) Δt + â Δt² / 2      (forecast(), motion_predictor.hpp)
//             which the filter uses at each measurement's own time on any clock.
// Inputs are scaled by the training data's typical speed s_v, step period s_t and a length s_p,
// stored in the model file.
//
// History spacing: the filter gives Φ history positions at least 0.9 training periods apart
// (kHistorySpacingFactor), however many unsynchronised views measure in between.
//
// Prediction horizon: Φ is trusted to predict across at most kHorizonFactor times the longest
// interval it trained on (the 99th percentile of the training histories' intervals, which with
// `stgf train --strides 1,2,3` is three steps); a track unseen for longer starts again.
//
// Process noise (DESIGN §1.2): Q is calibrated after training from Φ's one-step residuals
// r = y − x̂ on the validation split, Q_ref = E[r rᵀ] − E[P_last] (the part of the error the
// history's own uncertainty does not explain; eigenvalues floored at 1e-6 m²), at the validation
// split's median prediction interval Δt_ref. For another interval, Q(Δt) = Q_ref (Δt / Δt_ref)²
// (unmodelled acceleration). The user can override Q_ref.

#include <memory>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "stgf/core/motion_graph.hpp"
#include "stgf/core/motion_predictor.hpp"
#include "stgf/model/trained_motion_model.hpp"

namespace stgf {

class MotionModel final : public MotionPredictor {
 public:
  // A new model with random weights drawn from `seed`.
  MotionModel(const MotionModelShape& shape, const MotionNormalisation& normalisation, std::uint64_t seed);
  ~MotionModel() override;
  MotionModel(MotionModel&&) noexcept;
  MotionModel& operator=(MotionModel&&) noexcept;

  // Reads a model file written by save(), with the checks of TrainedMotionModel::load (which reads
  // it first: LibTorch then parses only archives that passed them). Throws InputError ("PATH:
  // reason") when the file is missing, corrupt, not a stgf motion model, or its weights do not match
  // its stated shape.
  static MotionModel load(const std::string& path);
  // Writes weights, shape, normalisation, Q and `metadata` (any JSON object) to `path`, whole or not at all.
  void save(const std::string& path, const nlohmann::json& metadata = nlohmann::json::object()) const;

  // Φ's forecast f(τ) = (v_last + â Δt_last / 2) τ + â τ² / 2 of every object, for any τ (the graphs'
  // target times only need to follow their histories); predict() evaluates it at the target times.
  // An object with a single history position gets Φ's forecast with zero velocity input (in practice:
  // the constant-position model plus what its neighbours say). Runs the Eigen forward pass
  // (motion_inference.hpp): each object's forecast depends on its own graph only, not on the batch.
  std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const override;

  // Q for a prediction interval of `dt` seconds.
  Matrix3d process_noise(double dt) const override;
  int history_positions() const override { return shape().history_length + 1; }
  double typical_speed() const override { return normalisation().speed; }
  // kHistorySpacingFactor of the training data's frame period s_f.
  double history_spacing() const override { return motion_model_history_spacing(normalisation()); }
  double prediction_horizon() const override { return kHorizonFactor * normalisation().longest_interval; }
  double coasting_horizon() const override;        // motion_model_coasting_horizon
  double widest_history_spacing() const override;  // motion_model_widest_history_spacing
  Matrix3d coasting_process_noise(double dt) const override;
  // Q_ref at Δt_ref (and no longer intervals: they were calibrated with the Q before).
  void set_process_noise(const Matrix3d& reference, double reference_period);
  // Q calibrated at intervals beyond Δt_ref, of Φ's forecasts and of coasting tracks
  // (core/process_noise_curve.hpp; learn/filter_calibration.hpp).
  void set_process_noise_intervals(std::vector<IntervalNoise> intervals, std::vector<IntervalNoise> coasting);
  const std::vector<IntervalNoise>& process_noise_intervals() const;
  const std::vector<IntervalNoise>& coasting_process_noise_intervals() const;
  double process_noise_period() const;  // Δt_ref

  // The model for its current weights, without LibTorch: what a file save() writes now would load as,
  // forecasts bit for bit the same.
  TrainedMotionModel trained() const;

  const MotionModelShape& shape() const;
  const MotionNormalisation& normalisation() const;
  nlohmann::json metadata() const;  // as stored in the file (empty for a new model)

  struct Impl;
  Impl& impl() { return *impl_; }
  const Impl& impl() const { return *impl_; }

 private:
  explicit MotionModel(std::unique_ptr<Impl> impl);
  static MotionModel load_checked(const std::string& path);  // load() without the catch-all
  std::unique_ptr<Impl> impl_;
};

}  // namespace stgf
