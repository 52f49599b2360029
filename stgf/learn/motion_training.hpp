// SPDX-License-Identifier: Apache-2.0
#pragma once
// Training Φ (DESIGN §1.1–1.2): Adam on the mean Euclidean error of the one-step prediction,
// validation after every epoch, the best model kept (with the optimizer state, configuration,
// normalisation and the calibrated Q), deterministic for a seed.
//
//   loss = (1/N) Σ_i ‖x̂_i − y_i‖₂    over the objects of a batch of graphs,
//
// y = the truth, or without it what was measured at the target time (make_measured_training_graphs):
// its noise is independent of the prediction and symmetric about zero, so the prediction that
// minimises the expected loss is the same. Q_ref = E[r rᵀ] − E[P_last] − E[P_target] on the
// validation graphs (P_target = 0 for the truth). Each epoch reports the validation error against y
// and the mean negative log-likelihood of y under N(x̂, P_last + P_target + Q_ref), the score a
// measured target can be judged by.
//
// History source for fused inputs (how Φ learns to read fused positions):
//   kObserved             the histories as given (e.g. the `wls` fusion of the measurements);
//   kTruthWithMatchedNoise the true past positions plus fresh Gaussian noise with each history
//                          point's own covariance, drawn anew every epoch (augmentation).
// Validation always uses the histories as given, so the two schemes are compared on what Φ
// will see at run time.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "stgf/learn/motion_model.hpp"
#include "stgf/model/motion_graphs.hpp"

namespace stgf {

enum class HistoryNoise { kObserved, kTruthWithMatchedNoise };

struct MotionTrainingOptions {
  int epochs = 30;
  double learning_rate = 1e-3;
  int batch_graphs = 64;       // graphs per optimisation step
  std::uint64_t seed = 1;
  // LibTorch intra-op threads; 0 = all cores. One by default: measured on a 2-core machine with
  // another job running, 2 threads took 1.1× (OpenMP threads sleeping) to 2.5× (spinning) the time of
  // one (bench/README.md). A model's bytes depend on the count (float sums in another order).
  int threads = 1;
  std::string resume;          // model file to continue from (its optimizer state too), or empty
  // false: the model file leaves out Adam's state (a third the size: what a model shipped to users
  // needs); it runs as before, and resuming from it starts Adam afresh.
  bool keep_optimizer_state = true;
  // true: the model file stores the weights as float16 (half its size: what a model shipped to users
  // needs). The network trains in float32; the file, and every run from it, has the rounded weights,
  // and Q and the registration prior are calibrated with them.
  bool weights_float16 = false;
  HistoryNoise history = HistoryNoise::kObserved;
  // Each training graph turned about the vertical axis by an angle drawn uniformly every epoch, so
  // that Φ learns motion whatever the world frame's heading (the validation graphs stay as given).
  bool rotate = false;
  MotionModelShape shape;
  // s_f, the frame period of the fastest training benchmark (MotionNormalisation::frame_period; 0: the
  // training intervals' median s_t, right for one benchmark). Not for a resumed model, which keeps its own.
  double frame_period = 0.0;
  nlohmann::json metadata = nlohmann::json::object();  // stored in the model file (e.g. the input kind)
};

struct EpochReport {
  int epoch = 0;                // 1-based
  double train_loss = 0.0;      // mean Euclidean error over the epoch's batches (m)
  double validation_error = 0.0;  // mean Euclidean error on validation (m)
  double validation_nll = 0.0;    // mean negative log-likelihood of the validation targets (nats)
  double seconds = 0.0;
};

struct TrainingProgress {
  int epoch = 0, epochs = 0;
  int batch = 0, batches = 0;
  double loss = 0.0;           // running mean of this epoch
  double elapsed_seconds = 0.0;  // since training started
  const EpochReport* finished_epoch = nullptr;  // set once per epoch, after validation
};

struct TrainingReport {
  std::vector<EpochReport> epochs;
  std::optional<double> initial_validation_nll;  // of the untrained model (none when resuming)
  // Resumed from a file without the optimizer's state (keep_optimizer_state false): Adam started afresh.
  bool resumed_without_optimizer_state = false;
  // Resuming: the resumed model's validation error on this validation split, before any epoch.
  std::optional<double> resumed_validation_error;
  int best_epoch = 0;
  double best_validation_error = 0.0;
  double constant_velocity_validation_error = 0.0;  // the same graphs predicted at constant velocity
  Matrix3d process_noise = Matrix3d::Zero();        // calibrated Q_ref
  double process_noise_period = 0.0;                // Δt_ref
  std::size_t train_objects = 0, validation_objects = 0;
  // Training stops at the first non-finite loss or validation error (the weights are then lost); the
  // epoch and batch where it happened (batch 0: in validation), 0 when it did not.
  int diverged_epoch = 0;
  int diverged_batch = 0;
};

// Trains Φ and writes the best model to `model_path` each time an epoch improves on the best so far
// (best_epoch stays 0 when none did: nothing written). Resuming, the resumed model is validated on
// `validation` first and written as the best so far (best_epoch: its own last epoch, with this
// training's metadata), so that a model trained on other data can be fine-tuned on these: an epoch
// must beat it here, not where it came from. A non-finite loss stops training (diverged_epoch). std::invalid_argument for empty data
// or bad options. Callers that must not expose a half-trained model give a working path and move
// it into place at the end (apps/stgf/training_pipeline.cpp).
TrainingReport train_motion_model(const std::vector<TrainingGraph>& train, const std::vector<TrainingGraph>& validation,
                                  const MotionTrainingOptions& options, const std::string& model_path,
                                  const std::function<void(const TrainingProgress&)>& progress = {});

// Rewrites `path`, a model file from train_motion_model, with `model`'s Q and `metadata`, keeping the
// file's optimizer state (so --resume continues where training stopped).
void save_recalibrated_model(const MotionModel& model, const std::string& path, const nlohmann::json& metadata);

// Normalisation measured on training graphs: typical speed (RMS of history velocities, at least
// 0.1 m/s), median step period, and a fixed 5 m length scale.
MotionNormalisation measure_normalisation(const std::vector<TrainingGraph>& graphs);

// Mean Euclidean error of the constant-velocity prediction (last velocity × Δt) on the graphs.
double constant_velocity_error(const std::vector<TrainingGraph>& graphs);

}  // namespace stgf
