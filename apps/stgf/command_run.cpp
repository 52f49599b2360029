// SPDX-License-Identifier: Apache-2.0
// stgf run --method NAME --measurements M.csv --out E.csv [--config C.yaml]

#include <chrono>
#include <memory>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "gating_log.hpp"
#include "input_guard.hpp"
#include "learned_seam.hpp"
#include "stgf/core/scene_filter.hpp"
#include "stgf/core/steps.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/estimate_file.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/method_config_file.hpp"
#include "stgf/methods/run_method.hpp"

namespace stgf::cli {
namespace {

struct RunOptions {
  std::string method;
  std::string measurements;
  std::string out;
  std::string config;
  std::string model;
};

void run(const RunOptions& options) {
  refuse_output_over_input("--out", options.out, {options.measurements, options.config, options.model});
  if (!is_learned_method(options.method) && !options.model.empty()) {
    // Not ignored silently: the user may believe the model is in use.
    throw std::invalid_argument("--model is for the learned methods (sttp, ours-l, ours); --method " + options.method +
                                " uses no model");
  }
  const auto start = std::chrono::steady_clock::now();
  const MethodConfig config = options.config.empty() ? MethodConfig{} : read_method_config(options.config);
  // Before anything is read: in `stgf`, a learned method hands the command line over to stgf-learned.
  std::unique_ptr<LearnedMethod> learned;
  if (is_learned_method(options.method)) learned = prepare_learned_method(options.method, config, options.model);
  MeasurementFile measurements = read_measurements(options.measurements);
  std::vector<Gaussian3> positions;
  try {
    if (learned) {
      positions = learned->run(measurements.rows);
    } else {
      GatingSummary gating;
      positions = run_method(options.method, config, measurements.rows, &gating);
      if (options.method == "wls") log_gating(options.method, config.wls_gate, gating);
      if (options.method == "mmt") log_gating(options.method, config.mmt_gate, gating);
    }
  } catch (const LateMeasurementError& late) {
    throw InputError(options.measurements, measurements.lines.at(late.id()), late.what());
  }
  std::size_t steps = 0;
  const std::vector<Scene> scenes = group_into_scenes(measurements.rows);
  for (const Scene& scene : scenes) steps += scene.steps.size();

  // The measurements are done with: their names move into the estimates.
  std::vector<Estimate> estimates;
  estimates.reserve(positions.size());
  for (std::size_t k = 0; k < positions.size(); ++k) {
    Measurement& row = measurements.rows[k];
    estimates.push_back(
        Estimate{std::move(row.scene), row.time, std::move(row.view), std::move(row.object), positions[k]});
  }
  write_estimates(options.out, estimates, options.method);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  spdlog::info("{}: {} estimates ({} scenes, {} steps) from {} -> {} in {:.2f} s", options.method,
               estimates.size(), scenes.size(), steps, options.measurements, options.out, seconds);
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* command = app.add_subcommand(
      "run", "Run a localization method over a measurements file and write one estimate per measured row.");
  command->add_option("--method", options->method, "aom | wls | mmt | sttp | ours-l | ours")
      ->required()
      ->check(CLI::IsMember(all_method_names()));
  command->add_option("--measurements", options->measurements, "measurements CSV (scene,t,view,object,x,y,z,cov_*)")
      ->required();
  command->add_option("--out", options->out, "estimates CSV to write")->required();
  command->add_option("--config", options->config, "YAML method settings (see config/methods.yaml)");
  command->add_option("--model", options->model, "model file from stgf train (for sttp, ours-l and ours)");
  command->callback([options] { run(*options); });
}

}  // namespace stgf::cli
