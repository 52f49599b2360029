// SPDX-License-Identifier: Apache-2.0
#include "stgf/learn/named_methods.hpp"

#include <stdexcept>

#include "stgf/learn/learned_methods.hpp"
#include "stgf/learn/registration_metadata.hpp"
#include "stgf/methods/filter_runner.hpp"
#include "stgf/methods/run_method.hpp"

namespace stgf {

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

FilterOptions filter_options_for(const OursSettings& settings, const nlohmann::json& metadata,
                                 const std::string& model_path, bool* registration_missing) {
  FilterOptions options;
  options.registration = resolve_registration_prior(settings, metadata, model_path, registration_missing);
  options.adapt_process_noise = settings.adapt_process_noise;
  options.tracks = settings.per_view_tracks ? TrackMode::kPerView : TrackMode::kPerObject;
  options.lag_window = settings.lag_window;
  options.late = settings.stop_on_late ? LatePolicy::kStop : LatePolicy::kLeaveOut;
  options.gate = settings.gate;
  return options;
}

std::vector<Gaussian3> run_named_method(const std::string& method, const MethodConfig& config, const MotionModel* model,
                                        const std::string& model_path, std::span<const Measurement> rows,
                                        MethodRunReport* report) {
  MethodRunReport ignored;
  MethodRunReport& out = report != nullptr ? *report : ignored;
  out = MethodRunReport{};
  if (!is_learned_method(method)) return run_method(method, config, rows);
  if (model == nullptr) throw std::invalid_argument("--method " + method + " needs --model");
  if (method == "sttp") return run_single_view_prediction(*model, rows, &out.restarted_tracks);

  const FilterOptions options = filter_options_for(config.ours, model->metadata(), model_path, &out.registration_missing);
  const bool prediction_only = method == "ours-l";
  FilterRun run = run_spatiotemporal_graph_filter(*model, options, rows, /*keep_predictions=*/prediction_only);
  out.restarted_tracks = run.restarted_tracks;
  out.rewinds = run.rewinds;
  out.late_measurements = run.late_measurements;
  out.gating = std::move(run.gating);
  if (prediction_only) {
    for (std::size_t row = 0; row < rows.size(); ++row) {
      if (const auto& prediction = run.predictions[row]) run.estimates[row] = prediction->prior;
    }
  }
  return std::move(run.estimates);
}

}  // namespace stgf
