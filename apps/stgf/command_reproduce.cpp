// SPDX-License-Identifier: Apache-2.0
// stgf reproduce [--benchmarks mpl,cad] [--out DIR] [--quick] [--seed S] [--epochs N] [--threads N] [--portable]
//
// The paper's experiments end to end (DESIGN §2, §4, §5), for each benchmark:
//   1. build the benchmark at DIR/benchmarks/NAME, or reuse it when it was built with the same recipe;
//   2. train the models, or reuse them: DIR/models/NAME.pt (fused histories: ours-l, ours) and
//      DIR/models/NAME-sttp.pt (one view's raw histories: sttp);
//   3. run the six methods on the test split (DIR/estimates/NAME/METHOD.csv), and `ours` once more
//      without its registration-error handling;
//   4. score them from step 2 on (the same rows for every method);
// then write DIR/results.md (Table I, the paper comparison, registration on/off, DE by number of
// views, figures, timings), DIR/results.json, and the figures in DIR/figures (SVG and PNG by gnuplot).

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "learned_seam.hpp"
#include "input_guard.hpp"
#include "figures.hpp"
#include "install_layout.hpp"
#include "method_runner.hpp"
#include "reproduce_report.hpp"
#include "training_pipeline.hpp"
#include "stgf/core/steps.hpp"
#include "stgf/datasets/benchmark_folder.hpp"
#include "stgf/datasets/cad_benchmark.hpp"
#include "stgf/datasets/mpl_benchmark.hpp"
#include "stgf/io/estimate_file.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/evaluation_report.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/output_file.hpp"
#include "stgf/io/truth_file.hpp"

namespace stgf::cli {
namespace {

namespace fs = std::filesystem;

// Bump when training changes in a way that makes older reproduce models stale.
constexpr int kTrainingRecipeVersion = 8;  // 8: every model trained with --rotate (the default)
constexpr int kFromStep = 2;
const char* const kRegistrationOff = "ours-registration-off";
// `ours` with the paper's per-view tracks instead of one track per object.
const char* const kPerViewTracks = "ours-per-view";

struct ReproduceOptions {
  std::vector<std::string> benchmarks = {"mpl", "cad"};
  std::string out = "reproduce";
  bool quick = false;
  std::uint64_t seed = 1;
  int epochs = 0;   // 0: 8, or 3 with --quick
  int threads = 1;  // LibTorch threads for training (0: all cores)
  bool portable = false;  // generic LibTorch and OpenBLAS kernels (learned_seam.hpp)
  std::vector<int> instances;  // train, val, test instances; empty: the benchmark's defaults (or --quick's)
  std::string mpl_source;    // "": the shipped data (install_layout.hpp)
  std::string kitti_source;  // "": STGF_KITTI_DIR or share/stgf/kitti_tracking
};

class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

std::string read_text(const fs::path& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// A stamp, written when a benchmark or model is made: {"recipe": how it was made, "seconds": how
// long that took}. Returns the seconds when `stamp` holds exactly `recipe`.
std::optional<double> stamp_matches(const fs::path& stamp, const nlohmann::json& recipe) {
  if (!fs::exists(stamp)) return std::nullopt;
  const nlohmann::json stored = nlohmann::json::parse(read_text(stamp), nullptr, false);
  if (stored.is_discarded() || !stored.is_object() || stored.value("recipe", nlohmann::json()) != recipe) return std::nullopt;
  return stored.value("seconds", 0.0);
}

void write_stamp(const fs::path& stamp, const nlohmann::json& recipe, double seconds) {
  write_text_file(stamp.string(), nlohmann::json{{"recipe", recipe}, {"seconds", seconds}}.dump(2) + "\n");
}

int epochs_of(const ReproduceOptions& options) { return options.epochs > 0 ? options.epochs : options.quick ? 3 : 8; }

nlohmann::json benchmark_recipe(const std::string& name, const ReproduceOptions& options,
                                const ViewClockOptions& clocks = {}) {
  nlohmann::json recipe = {{"benchmark", name},
                           {"seed", options.seed},
                           {"quick", options.quick},
                           {"source", name == "mpl" ? options.mpl_source : options.kitti_source}};
  if (!options.instances.empty()) recipe["instances"] = options.instances;
  if (clocks.asynchronous || clocks.latency_s > 0.0) {
    recipe["clocks"] = {{"asynchronous", clocks.asynchronous}, {"jitter_s", clocks.jitter_s}, {"latency_s", clocks.latency_s}};
  }
  return recipe;
}

// The asynchronous variants of each benchmark: the same data with each view on its own clock (phase
// uniform in one frame period, 2 ms jitter), without and with message latency (uniform 0–150 ms).
struct ClockVariant {
  std::string suffix;  // of the benchmark's folder and name
  ViewClockOptions clocks;
};
std::vector<ClockVariant> clock_variants() {
  ViewClockOptions asynchronous;
  asynchronous.asynchronous = true;
  ViewClockOptions late = asynchronous;
  late.latency_s = 0.15;
  return {{"async", asynchronous}, {"async-latency", late}};
}

// The seed, source and split sizes of a benchmark's options (MplOptions or CadOptions): --quick's
// smaller sizes, or --instances when given.
template <typename BenchmarkOptions>
BenchmarkOptions sized_options(const ReproduceOptions& options, const std::string& source,
                               const std::array<int, 3>& quick_instances) {
  BenchmarkOptions benchmark;
  benchmark.seed = options.seed;
  benchmark.source_directory = source;
  std::array<int, 3> instances = {benchmark.train_instances, benchmark.val_instances, benchmark.test_instances};
  if (options.quick) instances = quick_instances;
  if (!options.instances.empty()) instances = {options.instances[0], options.instances[1], options.instances[2]};
  benchmark.train_instances = instances[0];
  benchmark.val_instances = instances[1];
  benchmark.test_instances = instances[2];
  return benchmark;
}

Benchmark make_benchmark(const std::string& name, const ReproduceOptions& options, const ViewClockOptions& clocks) {
  if (name == "mpl") {
    MplOptions mpl = sized_options<MplOptions>(options, options.mpl_source, {300, 150, 300});
    mpl.clocks = clocks;
    return make_mpl_benchmark(mpl);
  }
  CadOptions cad = sized_options<CadOptions>(options, options.kitti_source, {300, 100, 300});
  cad.clocks = clocks;
  return make_cad_benchmark(cad);
}

// The median interval between a scene's steps (the frame period of a synchronous split).
double frame_period(std::span<const Measurement> rows) {
  std::vector<double> intervals;
  for (const Scene& scene : group_into_scenes(rows)) {
    for (std::size_t k = 1; k < scene.steps.size(); ++k) intervals.push_back(scene.steps[k].time - scene.steps[k - 1].time);
  }
  if (intervals.empty()) return 0.0;
  std::nth_element(intervals.begin(), intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2), intervals.end());
  return intervals[intervals.size() / 2];
}

struct Progress {
  std::string benchmark;
  int stage = 0;
  static constexpr int kStages = 6;
  void next(const std::string& what) {
    ++stage;
    spdlog::info("[{} {}/{}] {}", benchmark, stage, kStages, what);
  }
};

void ensure_benchmark(const std::string& name, const fs::path& folder, const ReproduceOptions& options,
                      Progress& progress, std::map<std::string, double>& timings, const ViewClockOptions& clocks = {}) {
  const nlohmann::json recipe = benchmark_recipe(name, options, clocks);
  const fs::path stamp = folder / "reproduce-recipe.json";
  if (const auto seconds = stamp_matches(stamp, recipe); seconds && fs::exists(folder / "benchmark.json")) {
    progress.next("benchmark: reusing " + folder.string());
    timings["build benchmark (reused)"] = *seconds;
    return;
  }
  progress.next("benchmark: building " + folder.string());
  const Stopwatch watch;
  write_benchmark_folder(folder.string(), make_benchmark(name, options, clocks));
  timings["build benchmark"] = watch.seconds();
  write_stamp(stamp, recipe, timings["build benchmark"]);
}

void ensure_model(const std::string& name, const fs::path& benchmark, const fs::path& model, const std::string& input,
                  const ReproduceOptions& options, std::map<std::string, double>& timings) {
  ModelTraining training;
  training.benchmarks = {benchmark.string()};
  training.out = model.string();
  training.input = input;
  training.training.epochs = epochs_of(options);
  training.training.seed = options.seed;
  training.training.threads = options.threads;
  nlohmann::json recipe = {{"benchmark", benchmark_recipe(name, options)},
                           {"input", input},
                           {"epochs", training.training.epochs},
                           {"seed", options.seed},
                           {"training_recipe_version", kTrainingRecipeVersion}};
  // Fused models calibrate Q in the filter, also at longer intervals (stgf train's default).
  if (input == "fused") recipe["long_intervals_s"] = training.long_intervals;
  const fs::path stamp = fs::path(model.string() + ".recipe.json");
  if (const auto seconds = stamp_matches(stamp, recipe); seconds && fs::exists(model)) {
    spdlog::info("  model: reusing {}", model.string());
    timings["train " + input + " model (reused)"] = *seconds;
    return;
  }
  spdlog::info("  model: training {} on {} histories ({} epochs)", model.string(), input, epochs_of(options));
  const Stopwatch watch;
  fs::create_directories(model.parent_path());
  train_model(training);
  timings["train " + input + " model"] = watch.seconds();
  write_stamp(stamp, recipe, timings["train " + input + " model"]);
}

// Runs `method` over the test measurements and writes its estimates file; returns the file.
fs::path run_and_write(const std::string& method, const std::string& label, const MethodConfig& config,
                       const TrainedMotionModel* model, const std::string& model_path, const MeasurementFile& measurements,
                       const fs::path& folder, std::map<std::string, double>& timings) {
  const Stopwatch watch;
  const std::vector<Gaussian3> positions = run_method_and_log(method, config, model, model_path, measurements.rows);
  std::vector<Estimate> estimates;
  estimates.reserve(positions.size());
  for (std::size_t k = 0; k < positions.size(); ++k) {
    const Measurement& row = measurements.rows[k];
    estimates.push_back(Estimate{row.scene, row.time, row.view, row.object, positions[k]});
  }
  const fs::path file = folder / (label + ".csv");
  write_estimates(file.string(), estimates, label);
  timings["run " + label] = watch.seconds();
  spdlog::info("  {}: {} estimates in {:.1f} s", label, estimates.size(), timings["run " + label]);
  return file;
}

// The models of a benchmark, for run_every_method.
struct BenchmarkModels {
  const TrainedMotionModel& fused;
  fs::path fused_path;
  const TrainedMotionModel& raw;
  fs::path raw_path;
};

// Runs the six methods of Table I, then `ours` with each of `variants` (label, settings), over
// `measurements`, writing each one's estimates into `folder`; returns (label, file) in that order.
std::vector<std::pair<std::string, fs::path>> run_every_method(
    const BenchmarkModels& models, const std::vector<std::pair<std::string, MethodConfig>>& variants,
    const MeasurementFile& measurements, const fs::path& folder, std::map<std::string, double>& timings) {
  fs::create_directories(folder);
  std::vector<std::pair<std::string, fs::path>> files;
  const MethodConfig config;
  for (const std::string& method : all_method_names()) {
    const bool raw = method == "sttp";
    const TrainedMotionModel* model = raw ? &models.raw : is_learned_method(method) ? &models.fused : nullptr;
    const fs::path& model_path = raw ? models.raw_path : models.fused_path;
    files.emplace_back(method, run_and_write(method, method, config, model, model_path.string(), measurements, folder,
                                             timings));
  }
  for (const auto& [label, settings] : variants) {
    files.emplace_back(label, run_and_write("ours", label, settings, &models.fused, models.fused_path.string(),
                                            measurements, folder, timings));
  }
  return files;
}

std::vector<EstimateFile> read_all(const std::vector<std::pair<std::string, fs::path>>& files) {
  std::vector<EstimateFile> estimates;
  for (const auto& [label, file] : files) estimates.push_back(read_estimates(file.string()));
  return estimates;
}

void draw_figures(const std::string& name, const Evaluation& evaluation, const TruthFile& truth,
                  const std::map<std::string, fs::path>& estimate_files,
                  const fs::path& figures, bool draw, std::vector<std::string>& drawn) {
  Evaluation main_methods = evaluation;
  std::erase_if(main_methods.methods, [](const MethodScore& score) {
    return score.method == kRegistrationOff || score.method == kPerViewTracks;
  });
  const std::string views_stem = "views-" + name;
  write_views_curve(main_methods, figures.string(), views_stem,
                    "DE against the number of views (" + name + " test split, from step 2)");

  std::vector<EstimateFile> files;
  for (const std::string method : {"aom", "mmt", "ours-l", "ours"}) {
    files.push_back(read_estimates(estimate_files.at(method).string()));
  }
  const auto [scene, view] = busiest_scene_and_view(files.back().rows);
  std::vector<TruthPoint> scene_truth;
  for (const TruthPoint& point : truth.rows) {
    if (point.scene == scene) scene_truth.push_back(point);
  }
  const std::vector<MethodTrajectory> methods = trajectories_of(files, scene, view);
  const std::string trajectory_stem = "trajectories-" + name;
  write_trajectories(scene_truth, methods, figures.string(), trajectory_stem,
                     fmt::format("{} test scene {}, estimates held by {}", name, scene, view));
  if (!draw) return;
  for (const std::string& stem : {views_stem, trajectory_stem}) {
    run_gnuplot(figures.string(), stem);
    drawn.push_back(stem);
  }
}

BenchmarkResult reproduce_benchmark(const std::string& name, const ReproduceOptions& options, bool draw) {
  const fs::path out(options.out);
  const fs::path folder = out / "benchmarks" / name;
  BenchmarkResult result;
  result.name = name;
  Progress progress{name};
  ensure_benchmark(name, folder, options, progress, result.timings);

  progress.next("models");
  const fs::path fused_model = out / "models" / (name + ".pt");
  const fs::path raw_model = out / "models" / (name + "-sttp.pt");
  ensure_model(name, folder, fused_model, "fused", options, result.timings);
  ensure_model(name, folder, raw_model, "raw", options, result.timings);

  progress.next("running the six methods on the test split");
  const MeasurementFile measurements = read_measurements((folder / "test" / "measurements.csv").string());
  const TrainedMotionModel fused = load_model_for("ours", fused_model.string());
  const TrainedMotionModel raw = load_model_for("sttp", raw_model.string());
  const BenchmarkModels models{fused, fused_model, raw, raw_model};
  MethodConfig without_registration;
  without_registration.ours.registration = false;
  MethodConfig per_view;
  per_view.ours.per_view_tracks = true;
  const auto written = run_every_method(models, {{kRegistrationOff, without_registration}, {kPerViewTracks, per_view}},
                                        measurements, out / "estimates" / name, result.timings);
  const std::map<std::string, fs::path> estimate_files(written.begin(), written.end());

  progress.next(fmt::format("scoring from step {} on", kFromStep));
  const TruthFile truth = read_truth((folder / "test" / "truth.csv").string());
  result.evaluation = evaluate(truth, read_all(written), &measurements, kFromStep);
  result.registration = fused.metadata().value("registration", nlohmann::json::object());

  progress.next(draw ? "figures" : "figures: gnuplot not found, writing data and scripts only");
  draw_figures(name, result.evaluation, truth, estimate_files, out / "figures", draw, result.figures);

  // The same test data on unsynchronised clocks, scored from the same point in time (two frame periods).
  progress.next("asynchronous views: the test split with each view on its own clock, without and with latency");
  const double from_time = kFromStep * frame_period(measurements.rows) - 1e-3;
  for (const ClockVariant& variant : clock_variants()) {
    const std::string variant_name = name + "-" + variant.suffix;
    const fs::path variant_folder = out / "benchmarks" / variant_name;
    Progress quiet{variant_name};
    std::map<std::string, double> timings;
    ensure_benchmark(name, variant_folder, options, quiet, timings, variant.clocks);
    const MeasurementFile rows = read_measurements((variant_folder / "test" / "measurements.csv").string());
    const auto variant_files = run_every_method(models, {{kRegistrationOff, without_registration}}, rows,
                                                out / "estimates" / variant_name, timings);
    for (const auto& [stage, seconds] : timings) result.timings[variant.suffix + ": " + stage] = seconds;
    const TruthFile variant_truth = read_truth((variant_folder / "test" / "truth.csv").string());
    result.clock_variants.push_back(
        {variant.suffix, variant.clocks.latency_s, evaluate(variant_truth, read_all(variant_files), &rows, ScoringStart{0, from_time})});
  }
  return result;
}

void reproduce(const ReproduceOptions& options) {
  const Stopwatch watch;
  for (const std::string& name : options.benchmarks) {
    if (name != "mpl" && name != "cad") throw std::invalid_argument("--benchmarks: unknown benchmark '" + name + "' (known: mpl, cad)");
  }
  const bool wants_cad = std::find(options.benchmarks.begin(), options.benchmarks.end(), "cad") != options.benchmarks.end();
  if (wants_cad && !fs::is_directory(options.kitti_source)) {
    throw InputError(options.kitti_source, 0,
                     "no KITTI tracking folder here; cad is built from KITTI (not shipped, see data/README.md): give "
                     "--kitti-source, or run --benchmarks mpl");
  }
  if (!options.instances.empty() && options.instances.size() != 3) {
    throw std::invalid_argument("--instances takes three numbers: train,val,test");
  }
  const bool draw = gnuplot_available();
  if (!draw) spdlog::warn("gnuplot not found: figures get their data and scripts, not their images (apt-get install gnuplot-nox)");
  std::vector<BenchmarkResult> results;
  for (const std::string& name : options.benchmarks) results.push_back(reproduce_benchmark(name, options, draw));

  ReproduceSummary summary;
  summary.command = fmt::format("stgf reproduce --benchmarks {} --out {} --seed {}{}", fmt::join(options.benchmarks, ","),
                                options.out, options.seed, options.quick ? " --quick" : "");
  summary.seed = options.seed;
  summary.quick = options.quick;
  summary.epochs = epochs_of(options);
  summary.from_step = kFromStep;
  summary.registration_off_label = kRegistrationOff;
  summary.per_view_label = kPerViewTracks;
  const fs::path out(options.out);
  write_text_file((out / "results.md").string(), results_markdown(summary, results));
  write_text_file((out / "results.json").string(), results_json(summary, results).dump(2) + "\n");
  std::fputs(table_one_markdown(results, summary.variant_labels()).c_str(), stdout);
  spdlog::info("results in {} (results.md, results.json, figures/) after {:.0f} s", options.out, watch.seconds());
}

}  // namespace

void add_reproduce_command(CLI::App& app) {
  auto options = std::make_shared<ReproduceOptions>();
  CLI::App* command = app.add_subcommand("reproduce", kReproduceDescription);
  command->add_option("--benchmarks", options->benchmarks, "comma-separated: mpl (built-in PETS 2009 data), cad (KITTI)")
      ->delimiter(',')
      ->capture_default_str();
  command->add_option("--out", options->out, "output folder (benchmarks, models and estimates in it are reused)")
      ->capture_default_str();
  command->add_flag("--quick", options->quick,
                    "smaller benchmarks (mpl 300/150/300, cad 300/100/300 instances) and 3 epochs: minutes, not tens of minutes");
  command->add_option("--seed", options->seed, "seed of the benchmarks and the training")->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command->add_option("--instances", options->instances,
                      "instances per split as train,val,test (default: the benchmark's, or --quick's sizes)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  command->add_option("--epochs", options->epochs, "training epochs (default 8, or 3 with --quick)")
      ->check(CLI::PositiveNumber);
  command->add_option("--threads", options->threads, "LibTorch threads for training (0: all cores; more are faster only on an idle machine)")->capture_default_str();
  command->add_flag(kPortableFlag, options->portable, kPortableFlagHelp);
  command->add_option("--mpl-source", options->mpl_source, "PETS 2009 S2L1 folder (default: the shipped one)");
  command->add_option("--kitti-source", options->kitti_source,
                      "KITTI tracking training folder, for cad (default: $STGF_KITTI_DIR, else share/stgf/kitti_tracking)");
  command->callback([options] {
    if (options->portable) ensure_portable_kernels();
    ReproduceOptions resolved = *options;
    if (resolved.mpl_source.empty()) resolved.mpl_source = shipped_data_directory() + "/pets2009_s2l1";
    if (resolved.kitti_source.empty()) resolved.kitti_source = default_kitti_directory();
    // What reproduce writes under --out; the source data may not be there.
    const fs::path out(resolved.out);
    std::vector<std::string> written;
    for (const char* part : {"benchmarks", "models", "estimates", "figures", "results.md", "results.json"}) {
      written.push_back((out / part).string());
    }
    refuse_outputs_over_inputs("--out", written, {resolved.mpl_source, resolved.kitti_source});
    reproduce(resolved);
  });
}

}  // namespace stgf::cli
