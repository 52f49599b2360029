// SPDX-License-Identifier: Apache-2.0
// stgf run --method NAME --measurements M.csv --out E.csv [--config C.yaml]
//
// The file is read, fused and written a block of scenes at a time (DESIGN §3.8: kScenesPerFilterBlock
// scenes for ours and ours-l, one for the others), so memory holds a block, not the file; the
// estimates are those of one run over the whole file. They go to a temporary file that is renamed into place only once every row is done: a bad
// row anywhere leaves no output and whatever --out held before.

#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "block_method.hpp"
#include "commands.hpp"
#include "input_guard.hpp"
#include "learned_seam.hpp"
#include "stgf/core/scene_filter.hpp"
#include "stgf/core/steps.hpp"
#include "stgf/io/estimate_file.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/method_config_file.hpp"
#include "stgf/methods/filter_runner.hpp"

namespace stgf::cli {
namespace {

struct RunOptions {
  std::string method;
  std::string measurements;
  std::string out;
  std::string config;
  std::string model;
};

// Writes the estimates in file order as the method gives them back. A block's rows are written as
// soon as their estimates come (at once, for every method but sttp, whose last forward pass may wait
// for the next block); rows still waiting keep their names until then, so the block itself can be
// read over. The file is made with the first estimate, so that a bad first block is reported before
// any file exists (as when the input was read whole), and is renamed into place only by commit().
class EstimateOutput {
 public:
  EstimateOutput(std::string path, std::string method) : path_(std::move(path)), method_(std::move(method)) {}

  // The next estimates, in file order: those of the rows still waiting, then of `block`'s rows.
  void write(const std::vector<Gaussian3>& estimates, const MeasurementFile& block) {
    std::size_t next = 0;
    for (; next < estimates.size() && !waiting_.empty(); ++next) {
      const Row& row = waiting_.front();
      writer().write(row.scene, row.time, row.view, row.object, estimates[next]);
      waiting_.pop_front();
    }
    if (estimates.size() - next > block.rows.size()) throw std::logic_error("stgf run: an estimate for no row");
    std::size_t row = 0;
    for (; next < estimates.size(); ++next, ++row) {
      const Measurement& measurement = block.rows[row];
      writer().write(measurement.scene, measurement.time, measurement.view, measurement.object, estimates[next]);
    }
    written_ += estimates.size();
    for (; row < block.rows.size(); ++row) {
      const Measurement& measurement = block.rows[row];
      waiting_.push_back({measurement.scene, measurement.time, measurement.view, measurement.object});
    }
  }

  // Every row has its estimate: the file goes into place.
  void commit() {
    if (!waiting_.empty()) throw std::logic_error("stgf run: a row got no estimate");
    writer().commit();
  }

  std::size_t written() const { return written_; }

 private:
  struct Row {
    std::string scene;
    double time;
    std::string view;
    std::string object;
  };

  EstimateWriter& writer() {
    if (!writer_) writer_.emplace(path_, method_);
    return *writer_;
  }

  std::string path_;
  std::string method_;
  std::optional<EstimateWriter> writer_;
  std::deque<Row> waiting_;
  std::size_t written_ = 0;
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
  // Before anything is read: a learned method's model is loaded and checked (a bad model file is an error
  // before any output).
  const std::unique_ptr<BlockMethod> method = is_learned_method(options.method)
                                                  ? prepare_learned_method(options.method, config, options.model)
                                                  : prepare_model_free_method(options.method, config);
  MeasurementSceneReader reader = MeasurementSceneReader::open(options.measurements);
  EstimateOutput output(options.out, options.method);
  std::size_t scenes = 0;
  std::size_t steps = 0;
  MeasurementFile block;
  while (const std::size_t read = reader.read(block, method->scenes_per_block())) {
    scenes += read;
    for (const Scene& scene : group_into_scenes(block.rows)) steps += scene.steps.size();
    std::vector<Gaussian3> estimates;
    try {
      estimates = method->add(block.rows);
    } catch (const LateMeasurementError& late) {
      throw InputError(options.measurements, block.lines.at(late.id()), late.what());
    }
    output.write(estimates, block);
  }
  output.write(method->finish(), MeasurementFile{});
  method->log_report();
  output.commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  spdlog::info("{}: {} estimates ({} scenes, {} steps) from {} -> {} in {:.2f} s", options.method, output.written(),
               scenes, steps, options.measurements, options.out, seconds);
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* command = app.add_subcommand(
      "run", "Run a localization method over a measurements file and write one estimate per measured row.");
  command->add_option("--method", options->method, "aom | wls | mmt | sttp | ours-l | ours")
      ->required()
      ->check(CLI::IsMember(all_method_names()));
  command->add_option("--measurements", options->measurements,
                      "measurements CSV (scene,t,view,object,x,y,z,cov_*), each scene's rows together")
      ->required();
  command->add_option("--out", options->out, "estimates CSV to write")->required();
  command->add_option("--config", options->config, "YAML method settings (see config/methods.yaml)");
  command->add_option("--model", options->model,
                       "model file from stgf train (for sttp, ours-l and ours; without it, ours and ours-l use the "
                       "general model shipped with stgf, models/README.md)");
  command->callback([options] { run(*options); });
}

}  // namespace stgf::cli
