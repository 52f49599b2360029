// SPDX-License-Identifier: Apache-2.0
// stgf train --benchmark DIR --out MODEL.pt [--input raw|fused] [--epochs N] [--lr X] [--batch N]
//            [--seed S] [--threads N] [--portable] [--resume MODEL.pt] [--no-resume-state] [--history N] [--history-noise observed|matched]

#include <cstdint>

#include "commands.hpp"
#include "learned_seam.hpp"
#include "training_pipeline.hpp"

namespace stgf::cli {

void add_train_command(CLI::App& app) {
  auto options = std::make_shared<ModelTraining>();
  auto portable = std::make_shared<bool>(false);  // --portable: pin the kernels first (learned_seam.hpp)
  MotionTrainingOptions& t = options->training;
  CLI::App* command = app.add_subcommand("train", kTrainDescription);
  command->add_option("--benchmark", options->benchmarks,
                      "benchmark folder (train/ and val/); several (comma-separated) train one model on all of them")
      ->delimiter(',')
      ->required();
  command->add_option("--out", options->out, "model file to write (the best epoch's model)")->required();
  command->add_option("--input", options->input, "histories Φ learns from: raw (one view's measurements, for sttp) "
                                                 "or fused (all views fused, for ours-l and ours)")
      ->capture_default_str()
      ->check(CLI::IsMember({"raw", "fused"}));
  command->add_option("--supervision", options->supervision,
                      "what Φ learns to predict: truth (truth.csv), measurements (the next fused measurement: for "
                      "recordings without truth; the registration prior and Q are calibrated from the views' "
                      "disagreements and innovations), or auto (truth when both splits have truth.csv, measurements "
                      "when neither has)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "truth", "measurements"}));
  command->add_option("--history-noise", options->history_noise,
                      "training histories: observed (as in the data), matched (truth + noise with each "
                      "position's covariance, drawn every epoch), or auto (matched for fused with truth, observed "
                      "otherwise)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "observed", "matched"}));
  command->add_option("--strides", options->strides,
                      "also train on the scenes at 1/stride of their frame rate, for each stride (1: as recorded)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_option("--long-intervals", options->long_intervals,
                      "also calibrate Q in the filter at intervals up to this many seconds (the validation split "
                      "thinned out), so that tracks coast across missed frames and low frame rates instead of "
                      "starting again (0: off, Q grows as the interval squared and tracks restart beyond the "
                      "model's horizon)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--rotate,!--no-rotate", options->rotate,
                    "turn each training scene by a random heading every epoch, so that the model does not learn the "
                    "world frame's orientation (the default; --no-rotate keeps the scenes as recorded, for a model "
                    "that only ever sees one world frame)");
  command->add_option("--epochs", t.epochs, "training epochs")->capture_default_str()->check(CLI::PositiveNumber);
  command->add_option("--lr", t.learning_rate, "Adam learning rate")->capture_default_str()->check(CLI::PositiveNumber);
  command->add_option("--batch", t.batch_graphs, "graphs per optimisation step")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->add_option("--seed", t.seed, "random seed; the same seed gives the same model")->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--threads", t.threads, "LibTorch threads for training (0: all cores; more are faster only on an idle machine)")->capture_default_str();
  command->add_flag(kPortableFlag, *portable, kPortableFlagHelp);
  command->add_option("--resume", t.resume,
                      "continue from this model file (weights and optimizer state), on this --benchmark: the model is "
                      "validated here first and kept unless an epoch does better (so models/general.pt can be "
                      "fine-tuned on your data)");
  command->add_flag("!--no-resume-state", t.keep_optimizer_state,
                    "leave the optimizer's state out of the model file: a third the size (a model to ship); it runs "
                    "as before, and --resume from it starts the optimizer afresh");
  command->add_option("--weights", options->weights, "how the model file stores the weights: float32, or float16 "
                      "(half the file; the network trains in float32, and the file's rounded weights are the model, "
                      "calibrated and run as such)")
      ->check(CLI::IsMember({"float32", "float16"}))
      ->capture_default_str();
  command->add_option("--noise-ratio", options->noise_ratio,
                      "the registration prior's offset in units of the noise: one α for all three axes, per-axis: "
                      "one each along, across and vertical to the measurements' rays (a zero on an axis cannot be "
                      "scaled out of on other data), or auto: per-axis for one benchmark whose views all stand still "
                      "(cameras: tilt and pan errors differ), else one (docs/design.md §1.7)")
      ->check(CLI::IsMember({"auto", "one", "per-axis"}))
      ->capture_default_str();
  command->add_flag_function(
      "--range-scale,!--no-range-scale",
      [options](std::int64_t count) { options->range_scale = count > 0; },
      "calibrate (or not) a scale of each view's horizontal range about its sensor (a ground-plane camera's "
      "height error, a range sensor's scale error; needs sensor_x, sensor_y in the rows); default: for one "
      "benchmark whose views all stand still (on cameras 3x and 5x worse calibrated than the training "
      "data, without it the covariance is too narrow: docs/design.md §1.7)");
  command->add_option("--history", t.shape.history_length, "history intervals Φ sees")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  command->callback([options, portable] {
    if (*portable) ensure_portable_kernels();
    train_model(*options);
  });
}

}  // namespace stgf::cli
