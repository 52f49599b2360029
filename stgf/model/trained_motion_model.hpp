// SPDX-License-Identifier: Apache-2.0
#pragma once
// Φ as trained: a model file (design.md §3.6) read without LibTorch, and its forecasts by the Eigen
// forward pass (motion_inference.hpp). Everything that runs a model — `stgf run` with sttp, ours-l or
// ours, the Python module, the examples — needs only this; LibTorch is for training
// (learn/motion_model.hpp, whose MotionModel::trained() gives the same model for its current weights).
//
// The file is a LibTorch archive (torch_archive.hpp); read here, it is checked as MotionModel::load
// checks it: the format marker and version, the configuration, every weight of the network with the
// shape the configuration states (motion_network_parameters()) and finite, and the checksum of
// version 2 files. The forecasts are bit for bit those of the MotionModel the file came from.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "stgf/core/motion_predictor.hpp"
#include "stgf/core/process_noise_curve.hpp"
#include "stgf/model/motion_inference.hpp"

namespace stgf {

struct MotionModelShape {
  int history_length = 8;        // H: history intervals the encoder sees
  int embedding = 16;            // input embedding
  int hidden = 32;               // encoder and decoder LSTM hidden size (m_i)
  int attention_hidden = 16;     // first graph-attention layer's output (the second outputs `hidden`)
  int max_fully_connected = 16;  // graphs up to this size are fully connected
  int nearest_neighbours = 8;    // larger graphs: each object attends to its k nearest (and itself)
};

// How inputs are scaled; measured on the training data.
struct MotionNormalisation {
  double speed = 1.0;             // s_v (m/s)
  double period = 0.1;            // s_t (s)
  double length = 5.0;            // s_p (m)
  double longest_interval = 0.3;  // the 99th percentile of the training intervals (s)
  // s_f: the frame period of the fastest training data (s) — of several benchmarks, the shortest of
  // their frame periods (each the median interval of its every-step histories); of one, s_t. A model
  // trained on data at 10, 7 and 2.5 Hz has s_t at whichever rate gave the most intervals, but Φ
  // learnt to read histories spaced 0.1 s apart: its history positions are spaced by s_f (below).
  // 0: s_t (one benchmark's).
  double frame_period = 0.0;
  double frame_period_or_period() const { return frame_period > 0.0 ? frame_period : period; }  // s_f
};

// Φ predicts across up to this many times the longest interval it trained on (the rate
// independence of its output is tested at twice and half the training rate).
inline constexpr double kHorizonFactor = 2.0;
// With Q calibrated at longer intervals (process_noise_curve.hpp), constant velocity takes over from
// Φ for a track whose history positions are further apart than this many times the longest interval
// Φ trained on (a little more than it, for jitter): Φ never saw such histories.
inline constexpr double kCoastingStartFactor = 1.25;
// Φ's history positions are at least this fraction of its training data's frame period s_f apart
// (motion_predictor.hpp): measurements on asynchronous clocks a few milliseconds apart refine a track's
// estimate, and a new history position starts once about a training frame period has passed (0.9, not
// 1, so that jitter in a stream at the training rate does not skip every other frame).
inline constexpr double kHistorySpacingFactor = 0.9;
inline double motion_model_history_spacing(const MotionNormalisation& normalisation) {
  return kHistorySpacingFactor * normalisation.frame_period_or_period();
}

// The model file's marker and newest version (1: the first format; 2 adds the checksum and keys
// Adam's state by parameter index; version 1 files are still read, without the check).
inline constexpr const char* kMotionModelFormat = "stgf-motion-model";
inline constexpr int kMotionModelVersion = 2;

// Everything of a model but its weights, as the file's `config` holds it.
struct MotionModelSettings {
  MotionModelShape shape;
  MotionNormalisation normalisation;
  Matrix3d process_noise_reference = Matrix3d::Zero();  // Q_ref (m²)
  double process_noise_period = 0.1;                    // Δt_ref (s)
  nlohmann::json metadata = nlohmann::json::object();
  // Q calibrated at intervals beyond Δt_ref (core/process_noise_curve.hpp); empty: Q ∝ Δt² throughout.
  std::vector<IntervalNoise> process_noise_intervals;
  // Q of a coasting track (constant velocity beyond Φ's horizon); empty: no track coasts.
  std::vector<IntervalNoise> coasting_process_noise;
};
// How long a track may go unseen: kHorizonFactor times the longest coasting interval Q was calibrated
// at, when there is one (and it is beyond Φ's horizon); else Φ's horizon.
double motion_model_coasting_horizon(const MotionNormalisation& normalisation,
                                     std::span<const IntervalNoise> coasting_process_noise);
// The widest history spacing Φ forecasts from. Infinite without coasting nodes (constant velocity
// cannot take over); else where Φ's curve of Q ends and the coasting curve starts, the geometric mean
// of Φ's last calibrated interval (Δt_ref without nodes) and the coasting curve's first (the
// calibration starts the coasting curve at the first interval where constant velocity predicted
// better than Φ, or beyond kCoastingStartFactor times the longest interval Φ trained on), and never
// beyond kCoastingStartFactor times that longest interval.
double motion_model_widest_history_spacing(const MotionNormalisation& normalisation, double process_noise_period,
                                           std::span<const IntervalNoise> process_noise_intervals,
                                           std::span<const IntervalNoise> coasting_process_noise);
// The `config` text of a model file, and back (std::invalid_argument with the reason).
nlohmann::json settings_json(const MotionModelSettings& settings);
MotionModelSettings settings_from_json(const nlohmann::json& config);

// One weight of the network: its name as LibTorch registers it and its shape.
struct MotionNetworkParameter {
  std::string name;
  std::vector<std::int64_t> sizes;
};
// The network's weights for `shape`, in LibTorch's parameter order (learn/motion_network.hpp
// registers them so; a test checks the two agree).
std::vector<MotionNetworkParameter> motion_network_parameters(const MotionModelShape& shape);

// A weight's values, row-major, by name.
struct NamedWeights {
  std::vector<std::string> names;
  std::vector<std::vector<float>> values;  // each the size of its parameter
  const std::vector<float>& at(const std::string& name) const;
};
// The forward pass's weights from the network's, checked against `shape`.
MotionNetworkWeights inference_weights(const MotionModelShape& shape, const NamedWeights& weights);
// The model file's checksum (FNV-1a, 64 bit, hex): over the config text and every weight's name,
// shape and bytes in motion_network_parameters() order.
std::string model_checksum(const std::string& config_text, const MotionModelShape& shape, const NamedWeights& weights);

// Φ's forecasts of every object of `graphs` (motion_model.hpp gives the math), each object from its
// own graph: what TrainedMotionModel::forecast and MotionModel::forecast run.
std::vector<std::vector<MotionForecast>> forecast_motion(const MotionInference& inference, const MotionModelShape& shape,
                                                         const MotionNormalisation& normalisation,
                                                         std::span<const MotionGraph> graphs);

class TrainedMotionModel final : public MotionPredictor {
 public:
  // Throws std::invalid_argument when the weights do not fit the shape.
  TrainedMotionModel(MotionModelSettings settings, const NamedWeights& weights);

  // Reads a model file written by `stgf train`. Throws InputError ("PATH: reason") when the file is
  // missing, corrupt, not a stgf motion model, or its weights do not match its stated shape.
  static TrainedMotionModel load(const std::string& path);
  // load() of the file's bytes (`path` names it in messages).
  static TrainedMotionModel parse(const std::string& bytes, const std::string& path);

  std::vector<std::vector<MotionForecast>> forecast(std::span<const MotionGraph> graphs) const override;
  Matrix3d process_noise(double dt) const override;  // Q_ref (dt / Δt_ref)²
  int history_positions() const override { return settings_.shape.history_length + 1; }
  double typical_speed() const override { return settings_.normalisation.speed; }
  double history_spacing() const override { return motion_model_history_spacing(settings_.normalisation); }
  double prediction_horizon() const override { return kHorizonFactor * settings_.normalisation.longest_interval; }
  double widest_history_spacing() const override {
    return motion_model_widest_history_spacing(settings_.normalisation, settings_.process_noise_period,
                                               settings_.process_noise_intervals, settings_.coasting_process_noise);
  }
  double coasting_horizon() const override {
    return motion_model_coasting_horizon(settings_.normalisation, settings_.coasting_process_noise);
  }
  Matrix3d coasting_process_noise(double dt) const override;

  const MotionModelShape& shape() const { return settings_.shape; }
  const MotionNormalisation& normalisation() const { return settings_.normalisation; }
  const nlohmann::json& metadata() const { return settings_.metadata; }
  const MotionModelSettings& settings() const { return settings_; }

 private:
  MotionModelSettings settings_;
  MotionInference inference_;
};

}  // namespace stgf
