// SPDX-License-Identifier: Apache-2.0
// stgf train's pipeline, shared with stgf reproduce.

#include "training_pipeline.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "input_guard.hpp"
#include "stgf/core/registration_calibration.hpp"
#include "stgf/core/sensor_motion.hpp"
#include "stgf/core/steps.hpp"
#include "stgf/io/input_error.hpp"
#include "stgf/io/measurement_file.hpp"
#include "stgf/io/truth_file.hpp"
#include "stgf/learn/filter_calibration.hpp"
#include "stgf/methods/run_method.hpp"
#include "stgf/methods/weighted_least_squares.hpp"
#include "stgf/model/motion_graphs.hpp"
#include "stgf/model/registration_metadata.hpp"

namespace stgf::cli {
namespace {

// A file that is removed when it goes out of scope unless moved into place.
class WorkingFile {
 public:
  explicit WorkingFile(std::string path) : path_(std::move(path)) { std::filesystem::remove(path_); }
  ~WorkingFile() {
    std::error_code ignored;
    if (!moved_) std::filesystem::remove(path_, ignored);
  }
  WorkingFile(const WorkingFile&) = delete;
  WorkingFile& operator=(const WorkingFile&) = delete;

  const std::string& path() const { return path_; }
  // Replaces `destination` in one step (rename(2) within one directory).
  void move_to(const std::string& destination) {
    std::filesystem::rename(path_, destination);
    moved_ = true;
  }

 private:
  std::string path_;
  bool moved_ = false;
};


struct Split {
  std::vector<TrainingGraph> graphs;
  // The frame period: the median interval of the every-step (stride 1) histories; of several
  // benchmarks, the shortest of theirs. 0 without any interval.
  double frame_period = 0.0;
  std::vector<Measurement> measurements;
  // Per row, where its object was: the truth, or (without truth) the fused measurement of the object
  // at the row's time with its covariance.
  std::vector<Vector3d> target_of_row;
  std::vector<Matrix3d> target_covariance_of_row;  // empty for the truth
};

// The kind of sensors of `measurements`' scenes (sensor_motion.hpp): one kind, or none where both occur.
std::optional<SensorMotion> sensors_of(std::span<const Measurement> measurements) {
  bool fixed = false, moving = false;
  for (const Scene& scene : group_into_scenes(measurements)) {
    (sensor_motion(measurements, scene) == SensorMotion::kMoving ? moving : fixed) = true;
  }
  if (fixed == moving) return std::nullopt;
  return fixed ? SensorMotion::kFixed : SensorMotion::kMoving;
}

// The median interval between consecutive history positions of `graphs` (0 without any).
double median_history_interval(const std::vector<TrainingGraph>& graphs) {
  std::vector<double> intervals;
  for (const TrainingGraph& graph : graphs) {
    for (const ObjectHistory& history : graph.graph.objects) {
      for (std::size_t k = 1; k < history.times.size(); ++k) {
        if (history.times[k] > history.times[k - 1]) intervals.push_back(history.times[k] - history.times[k - 1]);
      }
    }
  }
  if (intervals.empty()) return 0.0;
  const auto middle = intervals.begin() + static_cast<std::ptrdiff_t>(intervals.size() / 2);
  std::nth_element(intervals.begin(), middle, intervals.end());
  return *middle;
}

// `strides`: the graphs are made from the scenes at each of these fractions of the frame rate.
// `with_truth`: targets from truth.csv; else from the measurements alone.
Split read_split(const std::string& folder, HistorySource source, int history_length, bool with_truth,
                 const std::vector<int>& strides = {1}) {
  MeasurementFile measurements = read_measurements(folder + "/measurements.csv");
  Split split;
  std::optional<TruthIndex> index;
  if (with_truth) {
    const TruthFile truth = read_truth(folder + "/truth.csv");
    check_truth_matches(measurements, truth);
    index.emplace(truth);
    split.target_of_row.reserve(measurements.rows.size());
    for (const Measurement& row : measurements.rows) {
      split.target_of_row.push_back(*index->find(row.scene, row.time, row.object));
    }
  } else {
    // What was measured of each row's object at its time: the `wls` estimate (no gate).
    const auto wls = [] { return std::make_unique<WeightedLeastSquares>(); };
    for (const Gaussian3& fused : run_localizer(wls, measurements.rows)) {
      split.target_of_row.push_back(fused.mean());
      split.target_covariance_of_row.push_back(fused.covariance());
    }
  }
  for (const int stride : strides) {
    const std::vector<Measurement> strided_rows =
        stride == 1 ? std::vector<Measurement>() : every_nth_step(measurements.rows, stride);
    const std::span<const Measurement> rows = stride == 1 ? std::span<const Measurement>(measurements.rows) : strided_rows;
    const std::vector<TrainingGraph> graphs = with_truth ? make_training_graphs(rows, *index, source, history_length)
                                                         : make_measured_training_graphs(rows, source, history_length);
    if (stride == 1) split.frame_period = median_history_interval(graphs);
    split.graphs.insert(split.graphs.end(), graphs.begin(), graphs.end());
  }
  split.measurements = std::move(measurements.rows);
  return split;
}

// One split of several benchmarks: their graphs and rows one after the other. With more than one,
// each row's scene is prefixed by its benchmark's number ("2/scene"), so that scenes of different
// benchmarks with the same name stay apart.
Split read_splits(const std::vector<std::string>& benchmarks, const std::string& split, HistorySource source,
                  int history_length, bool with_truth, const std::vector<int>& strides = {1}) {
  if (benchmarks.size() == 1) return read_split(benchmarks[0] + split, source, history_length, with_truth, strides);
  Split all;
  for (std::size_t k = 0; k < benchmarks.size(); ++k) {
    Split one = read_split(benchmarks[k] + split, source, history_length, with_truth, strides);
    for (TrainingGraph& graph : one.graphs) graph.graph.scene = fmt::format("{}/{}", k + 1, graph.graph.scene);
    for (Measurement& row : one.measurements) row.scene = fmt::format("{}/{}", k + 1, row.scene);
    if (one.frame_period > 0.0 && (all.frame_period == 0.0 || one.frame_period < all.frame_period)) {
      all.frame_period = one.frame_period;
    }
    std::move(one.graphs.begin(), one.graphs.end(), std::back_inserter(all.graphs));
    std::move(one.measurements.begin(), one.measurements.end(), std::back_inserter(all.measurements));
    all.target_of_row.insert(all.target_of_row.end(), one.target_of_row.begin(), one.target_of_row.end());
    all.target_covariance_of_row.insert(all.target_covariance_of_row.end(), one.target_covariance_of_row.begin(),
                                        one.target_covariance_of_row.end());
  }
  return all;
}

// Whether to train against the truth: --supervision truth or measurements, or auto: truth when every
// split of every benchmark has a truth.csv, the measurements when none has.
bool trains_with_truth(const ModelTraining& options) {
  if (options.supervision == "truth") return true;
  if (options.supervision == "measurements") return false;
  std::optional<std::string> with, without;  // a split's truth file that exists, and one that does not
  for (const std::string& benchmark : options.benchmarks) {
    for (const char* split : {"/train/truth.csv", "/val/truth.csv"}) {
      std::optional<std::string>& seen = std::filesystem::exists(benchmark + split) ? with : without;
      if (!seen) seen = benchmark + split;
    }
  }
  if (with && without) {
    throw InputError(*without, 0,
                     fmt::format("missing, while {} exists: give every split its truth, or none to train from the "
                                 "measurements alone (or choose with --supervision truth|measurements)",
                                 *with));
  }
  return with.has_value();
}

std::string duration(double seconds) {
  const auto s = static_cast<long>(seconds + 0.5);
  return s >= 60 ? fmt::format("{}m{:02d}s", s / 60, s % 60) : fmt::format("{}s", s);
}

// A progress line on a terminal (rewritten in place at most ten times a second), one log line per
// epoch otherwise.
void show_progress(const TrainingProgress& p, bool terminal, double& last_shown) {
  if (p.finished_epoch != nullptr) {
    if (terminal) std::fputs("\r\033[K", stderr);
    const EpochReport& e = *p.finished_epoch;
    spdlog::info("epoch {}/{}: train {:.4f} m, validation {:.4f} m (NLL {:.3f}), {:.1f} s", e.epoch, p.epochs,
                 e.train_loss, e.validation_error, e.validation_nll, e.seconds);
    return;
  }
  if (!terminal || (p.elapsed_seconds - last_shown < 0.1 && p.batch < p.batches)) return;
  last_shown = p.elapsed_seconds;
  const double done = (p.epoch - 1) + static_cast<double>(p.batch) / p.batches;
  const double per_epoch = p.elapsed_seconds / std::max(done, 1e-9);
  const double remaining = per_epoch * std::max(0.0, p.epochs - done);
  const int width = 20;
  const int filled = static_cast<int>(width * static_cast<double>(p.batch) / p.batches);
  std::fprintf(stderr, "\r\033[Kepoch %d/%d [%s%s] batch %d/%d loss %.4f m ETA %s", p.epoch, p.epochs,
               std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(width - filled), ' ').c_str(), p.batch, p.batches, p.loss,
               duration(remaining).c_str());
  std::fflush(stderr);
}

// Q again, in the regime `ours` runs in: the filter over the validation split (filter_calibration.hpp).
void calibrate_in_filter(const std::string& model_path, const Split& validation, const RegistrationPrior& registration,
                         bool any_heading, double long_intervals) {
  const auto start = std::chrono::steady_clock::now();
  MotionModel model = MotionModel::load(model_path);
  const FilterCalibration calibration =
      calibrate_filter_process_noise(model, registration, validation.measurements,
                                     validation.target_of_row, validation.target_covariance_of_row, 5, any_heading);
  nlohmann::json rounds = nlohmann::json::array();
  for (const FilterCalibrationRound& round : calibration.rounds) {
    const Matrix3d& q = round.process_noise;
    if (round.stable) {
      spdlog::info("Q in the filter on the validation split: prediction error {:.4f} m, NEES {:.2f} -> Q at Δt = "
                   "{:.3f} s: diag({:.3g}, {:.3g}, {:.3g}) m²",
                   round.prior_error, round.prior_nees, calibration.period, q(0, 0), q(1, 1), q(2, 2));
    } else {
      spdlog::warn("Q in the filter on the validation split: prediction error {:.4g} m: the filter ran away with this "
                   "Q; half way back to the last Q it was stable with: diag({:.3g}, {:.3g}, {:.3g}) m²",
                   round.prior_error, q(0, 0), q(1, 1), q(2, 2));
    }
    rounds.push_back({{"prediction_error_m", round.prior_error}, {"prediction_nees", round.prior_nees}});
    if (!round.stable) rounds.back()["ran_away"] = true;
  }
  const FilterCalibrationRound& check = calibration.check;
  if (check.stable) {
    spdlog::info("Q in the filter on the validation split, checked: prediction error {:.4f} m, NEES {:.2f}",
                 check.prior_error, check.prior_nees);
  } else {
    const Matrix3d& q = check.process_noise;
    spdlog::warn("Q in the filter on the validation split, checked: prediction error {:.4g} m: the filter ran away "
                 "with the last Q; the model keeps the last Q it was stable with: diag({:.3g}, {:.3g}, {:.3g}) m²",
                 check.prior_error, q(0, 0), q(1, 1), q(2, 2));
  }
  nlohmann::json metadata = model.metadata();
  metadata["process_noise_calibration"] = {
      {"regime", "filter"},
      {"split", "val"},
      {"predictions", calibration.predictions},
      {"rounds", rounds},
      {"check", {{"prediction_error_m", check.prior_error}, {"prediction_nees", check.prior_nees}}}};
  if (!check.stable) metadata["process_noise_calibration"]["check"]["ran_away"] = true;
  if (long_intervals > 0.0) {
    const IntervalCalibrations calibrated =
        calibrate_process_noise_intervals(model, registration, validation.measurements, validation.target_of_row,
                                          validation.target_covariance_of_row, long_intervals, any_heading);
    const std::vector<IntervalCalibration>& intervals = calibrated.nodes;
    nlohmann::json nodes = nlohmann::json::array();
    for (const IntervalCalibration& node : intervals) {
      const Matrix3d& q = node.process_noise;
      const std::string rival =
          node.rival_error > 0.0 ? fmt::format(" ({} {:.4f} m)", node.coasting ? "Φ" : "constant velocity", node.rival_error)
                                 : std::string();
      spdlog::info("Q in the filter on the validation split every {} frames ({}): prediction error {:.4f} m{}, NEES "
                   "{:.2f} -> Q at Δt = {:.3f} s: diag({:.3g}, {:.3g}, {:.3g}) m²",
                   node.stride, node.coasting ? "constant velocity" : "Φ", node.prior_error, rival, node.prior_nees,
                   node.interval, q(0, 0), q(1, 1), q(2, 2));
      nodes.push_back({{"interval_s", node.interval}, {"coasting", node.coasting}, {"predictions", node.predictions},
                       {"prediction_error_m", node.prior_error}, {"prediction_nees", node.prior_nees}});
      if (node.rival_error > 0.0) nodes.back()["other_prediction_error_m"] = node.rival_error;
    }
    if (calibrated.diverged_at > 0.0) {
      spdlog::warn("Q calibrated up to {:.3f} s, not {:.3f} s: at {:.3f} s the filter ran away with the Q its first "
                   "round measured",
                   intervals.empty() ? calibration.period : intervals.back().interval, long_intervals,
                   calibrated.diverged_at);
    } else if (intervals.empty() || intervals.back().interval < long_intervals - 1e-9) {
      spdlog::warn("Q calibrated up to {:.3f} s, not {:.3f} s: the validation scenes are too short (or too few) for "
                   "{} predictions at longer intervals",
                   intervals.empty() ? calibration.period : intervals.back().interval, long_intervals,
                   kMinimumIntervalPredictions);
    }
    metadata["process_noise_calibration"]["intervals"] = nodes;
  }
  save_recalibrated_model(model, model_path, metadata);
  spdlog::info("Q calibrated in the filter in {:.1f} s",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace

void train_model(ModelTraining options) {
  if (options.benchmarks.empty()) throw std::invalid_argument("--benchmark needs at least one folder");
  std::vector<std::string> inputs = {options.training.resume};
  for (const std::string& benchmark : options.benchmarks) {
    for (const char* split : {"/train/", "/val/"}) {
      for (const char* file : {"measurements.csv", "truth.csv"}) inputs.push_back(benchmark + split + file);
    }
  }
  refuse_output_over_input("--out", options.out, inputs);
  const HistorySource source = options.input == "raw" ? HistorySource::kRawView : HistorySource::kFused;
  const bool with_truth = trains_with_truth(options);
  if (!with_truth && options.history_noise == "matched") {
    throw std::invalid_argument("--history-noise matched draws histories around the truth: without truth, train on "
                                "the histories as observed (--history-noise observed or auto)");
  }
  // auto: matched for fused histories when the truth is known (better on the validation splits of mpl
  // and cad, see docs/learning.md), observed for raw ones and without truth.
  const bool matched = options.history_noise == "matched" ||
                       (options.history_noise == "auto" && options.input == "fused" && with_truth);
  options.training.history = matched ? HistoryNoise::kTruthWithMatchedNoise : HistoryNoise::kObserved;
  options.training.rotate = options.rotate;
  options.training.weights_float16 = options.weights == "float16";
  // One benchmark is recorded as its folder, several as the list.
  const nlohmann::json benchmark_record =
      options.benchmarks.size() == 1 ? nlohmann::json(options.benchmarks[0]) : nlohmann::json(options.benchmarks);
  options.training.metadata = {{"input", options.input},
                               {"benchmark", benchmark_record},
                               {"strides", options.strides},
                               {"supervision", with_truth ? "truth" : "measurements"}};
  if (options.rotate) options.training.metadata["rotate"] = true;
  if (options.training.weights_float16) options.training.metadata["weights"] = "float16";
  if (options.strides.empty()) throw std::invalid_argument("--strides needs at least one stride");
  const int history = options.training.shape.history_length + 1;  // positions = intervals + 1
  const auto start = std::chrono::steady_clock::now();
  Split train = read_splits(options.benchmarks, "/train", source, history, with_truth, options.strides);
  const std::vector<TrainingGraph> train_graphs = std::move(train.graphs);
  // Φ's history positions are spaced by the fastest benchmark's frame period (MotionNormalisation).
  // (A resumed model keeps its own.)
  if (options.benchmarks.size() > 1 && train.frame_period > 0.0 && options.training.resume.empty()) {
    options.training.frame_period = train.frame_period;
    spdlog::info("history positions spaced by the fastest benchmark's frame period, {:.3g} s", train.frame_period);
  }
  const Split validation = read_splits(options.benchmarks, "/val", source, history, with_truth);
  // The views' registration prior, on the validation split (of every benchmark together). For a model
  // of one benchmark whose sensors all stand still (cameras), by default α per axis and a range scale:
  // a camera's tilt and pan errors differ, and its height error scales its ranges, which on cameras
  // worse calibrated than the training data's leaves the covariance too narrow without it (design
  // §1.7). Where they move, one α and no range scale (a vehicle's along-ray α calibrates to zero, which
  // no scale can undo on other data); and for a model of several benchmarks, which is meant for sensors
  // unlike its training data's, one α too (cameras' axes and range scale cost the model trained
  // without cad 19 % on cad's vehicles: design §1.7).
  const std::optional<SensorMotion> sensors = sensors_of(validation.measurements);
  const bool fixed_sensors = sensors == SensorMotion::kFixed;
  const bool cameras_model = fixed_sensors && options.benchmarks.size() == 1;
  const bool per_axis = options.noise_ratio == "per-axis" || (options.noise_ratio == "auto" && cameras_model);
  const bool range_scale = options.range_scale.value_or(cameras_model);
  const NoiseRatioAxes axes = per_axis ? NoiseRatioAxes::kPerAxis : NoiseRatioAxes::kOne;
  RegistrationCalibration calibrated =
      with_truth ? calibrate_registration_prior(validation.measurements, validation.target_of_row, axes, range_scale)
                 : calibrate_registration_prior_from_disagreements(validation.measurements, axes, range_scale);
  calibrated.prior.calibrated_sensors = sensors;
  if (options.rotate) {  // a prior that does not depend on the world frame's heading either
    Vector3d& sigma = calibrated.prior.translation_sigma;
    sigma.x() = sigma.y() = std::sqrt(0.5 * (sigma.x() * sigma.x() + sigma.y() * sigma.y()));
  }
  const std::vector<TrainingGraph>& validation_graphs = validation.graphs;
  spdlog::info("{} training and {} validation graphs ({} histories, targets: {}) read in {:.1f} s",
               train_graphs.size(), validation_graphs.size(), options.input,
               with_truth ? "the truth" : "the fused measurements (no truth)",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  const RegistrationPrior& registration = calibrated.prior;
  const Vector3d& ratio = registration.noise_ratio;
  spdlog::info("registration error on the validation split ({} {}): translation sigma ({:.3g}, {:.3g}, "
               "{:.3g}) m, noise ratio {}",
               calibrated.groups,
               with_truth ? "scene-views against the truth" : "scenes where views disagree",
               registration.translation_sigma.x(), registration.translation_sigma.y(),
               registration.translation_sigma.z(),
               ratio.isConstant(ratio.x())
                   ? fmt::format("{:.3g}", ratio.x())
                   : fmt::format("along, across, vertical to the rays ({:.3g}, {:.3g}, {:.3g})", ratio.x(), ratio.y(),
                                 ratio.z()));
  if (range_scale) spdlog::info("registration range scale sigma {:.3g}", registration.range_scale_sigma);
  spdlog::info("registration calibrated on {}", !sensors ? "sensors of both kinds (fixed and moving)"
                                                : fixed_sensors ? "fixed sensors: its shape is expected to hold on fixed ones"
                                                                : "moving sensors: its shape is expected to hold on moving ones");
  options.training.metadata["registration"] = registration_prior_to_json(registration);
  std::string calibrated_on;
  for (const std::string& benchmark : options.benchmarks) {
    calibrated_on += (calibrated_on.empty() ? "" : ",") + benchmark + "/val";
  }
  options.training.metadata["registration"]["calibrated_on"] = calibrated_on;
  options.training.metadata["registration"]["from"] = with_truth ? "truth" : "disagreements";
  if (!with_truth && calibrated.groups == 0) {
    spdlog::warn("no two views measure an object at the same time in {}: the registration prior stays zero "
                 "(no offsets assumed); views on their own clocks show their offsets only against the truth",
                 calibrated_on);
  }
  const bool terminal = ::isatty(::fileno(stderr)) != 0;
  double last_shown = -1.0;
  // The model is trained in a working file beside --out and moved into place only once it is
  // finished: a previous model at --out survives a failed or killed training. A working file left by
  // a killed run is removed here.
  WorkingFile working(options.out + ".training");
  const TrainingReport report = train_motion_model(
      train_graphs, validation_graphs, options.training, working.path(),
      [terminal, &last_shown](const TrainingProgress& p) { show_progress(p, terminal, last_shown); });
  if (report.resumed_validation_error) {
    spdlog::info("{} as resumed: validation error {:.4f} m on this validation split (the bar for the epochs){}",
                 options.training.resume, *report.resumed_validation_error,
                 report.resumed_without_optimizer_state
                     ? "; it holds no optimizer state (written with --no-resume-state): Adam started afresh"
                     : "");
  }
  if (report.diverged_epoch != 0) {
    const std::string where = report.diverged_batch > 0 ? fmt::format("batch {}", report.diverged_batch) : "validation";
    const std::string advice = fmt::format("lower --lr (now {:g}) or check the training data", options.training.learning_rate);
    if (report.best_epoch == 0 && options.training.resume.empty()) {
      throw std::runtime_error(fmt::format("training diverged in epoch {}, {} (the loss is not finite) before any epoch "
                                           "gave a model: nothing written, {} unchanged; {}",
                                           report.diverged_epoch, where, options.out, advice));
    }
    spdlog::warn("training diverged in epoch {}, {} (the loss is not finite) and stopped; keeping the best model so far; "
                 "{}",
                 report.diverged_epoch, where, advice);
  }
  if (report.best_epoch == 0 && options.training.resume.empty()) {
    throw std::runtime_error("no epoch gave a finite validation error: nothing written, " + options.out + " unchanged");
  }
  const Matrix3d& q = report.process_noise;
  // The NLL (mean negative log-likelihood of the validation targets under the prediction and its
  // covariance) of the best epoch, and of the untrained model (none when resuming).
  std::string likelihood;
  for (const EpochReport& epoch : report.epochs) {
    if (epoch.epoch == report.best_epoch) likelihood = fmt::format("; validation NLL {:.3f}", epoch.validation_nll);
  }
  if (!likelihood.empty() && report.initial_validation_nll) {
    likelihood += fmt::format(" (untrained: {:.3f})", *report.initial_validation_nll);
  }
  spdlog::info("best epoch {}: validation error {:.4f} m (constant velocity: {:.4f} m{}){}; Q at Δt = {:.3f} s: "
               "diag({:.3g}, {:.3g}, {:.3g}) m²",
               report.best_epoch, report.best_validation_error, report.constant_velocity_validation_error,
               with_truth ? "" : ", both against the fused measurements, whose own noise they include", likelihood,
               report.process_noise_period, q(0, 0), q(1, 1), q(2, 2));
  if (source == HistorySource::kFused) calibrate_in_filter(working.path(), validation, registration, options.rotate, options.long_intervals);
  MotionModel::load(working.path());  // finite weights of the stated shape, or InputError
  working.move_to(options.out);
  spdlog::info("model written to {}", options.out);
}

}  // namespace stgf::cli
