// SPDX-License-Identifier: Apache-2.0
#include "method_runner.hpp"

#include <stdexcept>

#include <spdlog/spdlog.h>

#include "stgf/learn/learned_methods.hpp"
#include "stgf/learn/registration_metadata.hpp"
#include "stgf/methods/filter_runner.hpp"
#include "stgf/methods/run_method.hpp"

namespace stgf::cli {

MotionModel load_model_for(const std::string& method, const std::string& model_path) {
  if (model_path.empty()) throw std::invalid_argument("--method " + method + " needs --model");
  MotionModel model = MotionModel::load(model_path);
  const std::string wanted = method == "sttp" ? "raw" : "fused";
  const std::string trained = model.metadata().value("input", "");
  if (trained != wanted) {
    throw std::invalid_argument(model_path + " was trained on " + (trained.empty() ? "unknown" : trained) +
                                " histories; --method " + method + " needs a model trained with --input " + wanted);
  }
  return model;
}

std::vector<Gaussian3> run_named_method(const std::string& method, const MethodConfig& config,
                                        const MotionModel* model, const std::string& model_path,
                                        std::span<const Measurement> rows) {
  if (!is_learned_method(method)) return run_method(method, config, rows);
  if (model == nullptr) throw std::invalid_argument("--method " + method + " needs --model");
  std::size_t restarted = 0;
  auto report_restarts = [&] {
    if (restarted == 0) return;
    spdlog::info("{}: {} track(s) started again: the object had not been seen for longer than the model's horizon "
                 "of {:.2f} s (twice the longest interval it trained on)",
                 method, restarted, model->prediction_horizon());
  };
  if (method == "sttp") {
    std::vector<Gaussian3> estimates = run_single_view_prediction(*model, rows, &restarted);
    report_restarts();
    return estimates;
  }
  bool missing = false;
  const RegistrationPrior registration = resolve_registration_prior(config.ours, model->metadata(), model_path, &missing);
  if (missing) {
    spdlog::warn("{} holds no registration calibration (trained before stgf calibrated it); the views' offsets are "
                 "taken as zero unless set under `ours:` in --config",
                 model_path);
  }
  FilterOptions options;
  options.registration = registration;
  options.adapt_process_noise = config.ours.adapt_process_noise;
  options.tracks = config.ours.per_view_tracks ? TrackMode::kPerView : TrackMode::kPerObject;
  options.lag_window = config.ours.lag_window;
  options.late = config.ours.stop_on_late ? LatePolicy::kStop : LatePolicy::kLeaveOut;
  // ours-l is the same filter's prediction of each row, before the update at its time (the row's own
  // fused estimate where there is nothing to predict from: a first sighting).
  const bool prediction_only = method == "ours-l";
  FilterRun run = run_spatiotemporal_graph_filter(*model, options, rows, /*keep_predictions=*/prediction_only);
  restarted = run.restarted_tracks;
  report_restarts();
  if (prediction_only) {
    for (std::size_t row = 0; row < rows.size(); ++row) {
      if (const auto& prediction = run.predictions[row]) run.estimates[row] = prediction->prior;
    }
  }
  if (run.rewinds > 0) {
    spdlog::info("{}: {} late row(s) fused in their place in time (arrived after later ones, within the lag window "
                 "of {} s)",
                 method, run.rewinds, options.lag_window);
  }
  if (run.late_measurements > 0) {
    spdlog::warn("{}: {} row(s) arrived more than the lag window of {} s late and were left out of the fusion "
                 "(each row's estimate is its own measurement)",
                 method, run.late_measurements, options.lag_window);
  }
  return std::move(run.estimates);
}

namespace {

class LoadedMethod final : public LearnedMethod {
 public:
  LoadedMethod(std::string method, MethodConfig config, std::string model_path)
      : method_(std::move(method)),
        config_(std::move(config)),
        model_path_(std::move(model_path)),
        model_(load_model_for(method_, model_path_)) {}

  std::vector<Gaussian3> run(std::span<const Measurement> rows) const override {
    return run_named_method(method_, config_, &model_, model_path_, rows);
  }

 private:
  std::string method_;
  MethodConfig config_;
  std::string model_path_;
  MotionModel model_;
};

}  // namespace

std::unique_ptr<LearnedMethod> prepare_learned_method(const std::string& method, const MethodConfig& config,
                                                      const std::string& model_path) {
  return std::make_unique<LoadedMethod>(method, config, model_path);
}

}  // namespace stgf::cli
