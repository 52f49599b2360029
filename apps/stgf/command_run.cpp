// stgf run --method NAME --measurements M.csv --out E.csv [--config C.yaml]

#include <chrono>
#include <optional>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "stgf/core/steps.hpp"
#include "stgf/io/estimate_file.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/method_config_file.hpp"
#include "stgf/learn/learned_methods.hpp"
#include "stgf/learn/registration_metadata.hpp"
#include "stgf/learn/spatiotemporal_graph_filter.hpp"
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
  const auto start = std::chrono::steady_clock::now();
  const MethodConfig config = options.config.empty() ? MethodConfig{} : read_method_config(options.config);
  const bool learned = options.method == "sttp" || options.method == "ours-l" || options.method == "ours";
  if (learned && options.model.empty()) throw std::invalid_argument("--method " + options.method + " needs --model");
  std::optional<MotionModel> model;
  if (learned) {
    model = MotionModel::load(options.model);
    const std::string wanted = options.method == "sttp" ? "raw" : "fused";
    const std::string trained = model->metadata().value("input", "");
    if (trained != wanted) {
      throw std::invalid_argument(options.model + " was trained on " + (trained.empty() ? "unknown" : trained) +
                                  " histories; --method " + options.method + " needs a model trained with --input " +
                                  wanted);
    }
  }
  RegistrationPrior registration;
  if (options.method == "ours") {
    bool missing = false;
    registration = resolve_registration_prior(config.ours, model->metadata(), options.model, &missing);
    if (missing) {
      spdlog::warn("{} holds no registration calibration (trained before stgf calibrated it); views' offsets are "
                   "taken as zero unless set under `ours:` in --config",
                   options.model);
    }
  }
  MeasurementFile measurements = read_measurements(options.measurements);
  const std::vector<Gaussian3> positions =
      options.method == "ours"
          ? run_localizer([&] { return std::make_unique<SpatiotemporalGraphFilter>(*model, registration); },
                          measurements.rows)
      : learned ? run_learned_method(options.method, *model, measurements.rows)
                : run_method(options.method, config, measurements.rows);
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
      ->check(CLI::IsMember({"aom", "wls", "mmt", "sttp", "ours-l", "ours"}));
  command->add_option("--measurements", options->measurements, "measurements CSV (scene,t,view,object,x,y,z,cov_*)")
      ->required();
  command->add_option("--out", options->out, "estimates CSV to write")->required();
  command->add_option("--config", options->config, "YAML method settings (see config/methods.yaml)");
  command->add_option("--model", options->model, "model file from stgf train (for sttp, ours-l and ours)");
  command->callback([options] { run(*options); });
}

}  // namespace stgf::cli
