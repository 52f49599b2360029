// SPDX-License-Identifier: Apache-2.0
#pragma once
// Training a model for the learned methods (stgf train, stgf reproduce):
//   1. read the benchmark's train/ and val/ splits (measurements, and truth if given: --supervision);
//   2. calibrate the views' registration prior on val (core/registration_calibration.hpp: against the
//      truth, or without it from the views' disagreements), stored in the model for `ours`;
//   3. train Φ (learn/motion_training.hpp) on the train split at each of `strides` (every step, every
//      2nd, every 3rd: lower frame rates), keeping the best epoch on val as recorded, Q calibrated
//      on Φ's residuals there;
//   4. fused input: calibrate Q again inside the filter on val (learn/filter_calibration.hpp).
// Without truth, every target is what was measured: the fused position of all views' measurements of
// the object at the target time (make_measured_training_graphs), and the histories are as observed.
// Progress goes to the log (and a live line on a terminal).
//
// The model is trained in OUT.training and renamed to OUT once finished and checked (finite weights of
// the stated shape): a failed, diverged or killed training leaves a previous OUT as it was. A loss
// that turns non-finite stops training; with no good epoch before it, nothing is written and the
// command fails (std::runtime_error). --out may not be one of the inputs (the benchmark's files, the
// --resume model): a usage error before anything is read.

#include <optional>
#include <string>
#include <vector>

#include "stgf/learn/motion_training.hpp"

namespace stgf::cli {

// `stgf train --long-intervals`'s default (s): a track may miss frames for up to about twice this and
// coast instead of starting again (design §1.9).
inline constexpr double kDefaultLongIntervals = 2.0;

struct ModelTraining {
  // Folders with train/ and val/; with several, Φ trains on all their training splits together,
  // and the registration prior and Q are calibrated on all their validation splits together.
  std::vector<std::string> benchmarks;
  std::string out;                     // model file to write
  std::string input = "fused";         // raw (sttp) | fused (ours-l, ours)
  std::string history_noise = "auto";  // observed | matched | auto (matched for fused, with truth)
  // truth | measurements | auto (truth when train/ and val/ have truth.csv, measurements when neither has)
  std::string supervision = "auto";
  // Φ also learns from the training scenes seen at 1/stride of their frame rate, for each stride
  // here (1 = as recorded), so it predicts at lower frame rates too.
  std::vector<int> strides = {1, 2, 3};
  std::string weights = "float32";  // how the model file stores the weights: float32 | float16
  // The registration prior's α: one for all three axes of δ, or one per axis of the rays' frame
  // (registration_calibration.hpp: NoiseRatioAxes): one | per-axis | auto (per axis for one benchmark
  // whose views all stand still, design §1.7).
  std::string noise_ratio = "auto";
  // Also calibrate σ_ε of each view's range scale (registration_calibration.hpp); false: none; unset
  // (auto): for one benchmark whose views all stand still.
  std::optional<bool> range_scale;
  bool rotate = true;  // turn each training graph by a random heading every epoch (MotionTrainingOptions::rotate)
  // Q also calibrated at intervals up to this many seconds (calibrate_process_noise_intervals), so that
  // tracks coast across missed frames and low frame rates; 0: off.
  double long_intervals = kDefaultLongIntervals;
  MotionTrainingOptions training;
};

void train_model(ModelTraining options);

}  // namespace stgf::cli
