// SPDX-License-Identifier: Apache-2.0
#include "stgf/learn/motion_training.hpp"

#include <algorithm>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>
#include <thread>

#include "stgf/core/cholesky3.hpp"
#include "stgf/core/eigenvalue_floor.hpp"
#include "stgf/learn/motion_network.hpp"

namespace stgf {
namespace {

constexpr int kValidationBatchGraphs = 512;
constexpr double kProcessNoiseFloor = 1e-6;  // m², smallest eigenvalue of a calibrated Q

struct Targets {
  torch::Tensor displacement;  // [N, 3]: y − p_last (m)
  torch::Tensor horizon;       // [N, 1]: Δt (s)
};

Targets targets_of(const std::vector<const TrainingGraph*>& graphs, const detail::MotionBatch& batch) {
  std::vector<float> displacement, horizon;
  std::size_t object = 0;
  for (const TrainingGraph* graph : graphs) {
    for (const Vector3d& target : graph->targets) {
      const Vector3d d = target - batch.last_positions[object];
      for (int axis = 0; axis < 3; ++axis) displacement.push_back(static_cast<float>(d(axis)));
      horizon.push_back(static_cast<float>(batch.horizons[object]));
      ++object;
    }
  }
  const auto n = static_cast<int64_t>(object);
  return {torch::from_blob(displacement.data(), {n, 3}, torch::kFloat32).clone(),
          torch::from_blob(horizon.data(), {n, 1}, torch::kFloat32).clone()};
}

// Per-object Euclidean error of the predicted displacement v̂ Δt against the true one.
torch::Tensor euclidean_errors(const torch::Tensor& velocity, const MotionNormalisation& normalisation,
                               const Targets& targets) {
  const torch::Tensor predicted = velocity * normalisation.speed * targets.horizon;
  return (predicted - targets.displacement).pow(2).sum(1).add(1e-12).sqrt();
}

std::vector<MotionGraph> graphs_of(const std::vector<const TrainingGraph*>& graphs) {
  std::vector<MotionGraph> result;
  result.reserve(graphs.size());
  for (const TrainingGraph* graph : graphs) result.push_back(graph->graph);
  return result;
}

// The graph with its history replaced by truth + N(0, P_k) for each history point.
TrainingGraph with_matched_noise(const TrainingGraph& source, std::mt19937_64& random) {
  if (source.true_histories.size() != source.targets.size()) {
    throw std::invalid_argument(
        "training histories of truth with matched noise need the truth: train on the "
        "histories as observed without it");
  }
  std::normal_distribution<double> normal;
  TrainingGraph noisy = source;
  for (std::size_t i = 0; i < noisy.graph.objects.size(); ++i) {
    ObjectHistory& history = noisy.graph.objects[i];
    for (std::size_t k = 0; k < history.positions.size(); ++k) {
      const Cholesky3 cholesky(source.history_covariances[i][k]);
      if (!cholesky.ok()) throw std::invalid_argument("training graph: history covariance is not positive definite");
      const double a = normal(random), b = normal(random), c = normal(random);
      history.positions[k] = source.true_histories[i][k] + cholesky.matrix_l() * Vector3d(a, b, c);
    }
  }
  return noisy;
}

// `source` turned by `angle` (rad) about the vertical axis through the origin: positions, targets
// and covariances (Φ reads differences of positions only, so the centre does not matter).
TrainingGraph rotated(TrainingGraph source, double angle) {
  const Matrix3d turn = Eigen::AngleAxisd(angle, Vector3d::UnitZ()).toRotationMatrix();
  for (std::size_t i = 0; i < source.graph.objects.size(); ++i) {
    for (Vector3d& position : source.graph.objects[i].positions) position = turn * position;
    if (i < source.true_histories.size()) {
      for (Vector3d& position : source.true_histories[i]) position = turn * position;
    }
    for (Matrix3d& covariance : source.history_covariances[i]) covariance = turn * covariance * turn.transpose();
    source.targets[i] = turn * source.targets[i];
    if (i < source.target_covariances.size()) {
      source.target_covariances[i] = turn * source.target_covariances[i] * turn.transpose();
    }
  }
  return source;
}

void check_graphs(const std::vector<TrainingGraph>& graphs, const char* name) {
  std::size_t objects = 0;
  for (const TrainingGraph& graph : graphs) {
    const auto matches = [&](std::size_t size, bool may_be_empty) {
      return size == graph.targets.size() || (may_be_empty && size == 0);
    };
    if (graph.targets.size() != graph.graph.objects.size() || !matches(graph.true_histories.size(), true) ||
        !matches(graph.target_covariances.size(), true) ||
        !matches(graph.history_covariances.size(), false)) {
      throw std::invalid_argument(std::string(name) + " graphs: targets and histories do not match the objects");
    }
    objects += graph.targets.size();
  }
  if (objects == 0) throw std::invalid_argument(std::string(name) + " data has no object to predict");
}

std::size_t count_objects(const std::vector<TrainingGraph>& graphs) {
  std::size_t objects = 0;
  for (const TrainingGraph& graph : graphs) objects += graph.targets.size();
  return objects;
}

// Q_ref = E[r rᵀ] − E[P_last] − E[P_target], eigenvalues floored. A measured target's own noise is in
// r (independent of the prediction's error), and E[P_target] takes it out again; the truth has none.
Matrix3d calibrated_process_noise(const Matrix3d& residual_moment, const Matrix3d& mean_known_covariance) {
  return symmetrised(with_eigenvalues_at_least(residual_moment - mean_known_covariance, kProcessNoiseFloor));
}

}  // namespace

MotionNormalisation measure_normalisation(const std::vector<TrainingGraph>& graphs) {
  double speed_squares = 0.0;
  std::size_t velocities = 0;
  std::vector<double> periods;
  for (const TrainingGraph& graph : graphs) {
    for (const ObjectHistory& history : graph.graph.objects) {
      for (std::size_t k = 1; k < history.positions.size(); ++k) {
        const double dt = history.times[k] - history.times[k - 1];
        if (!(dt > 0.0)) continue;
        speed_squares += ((history.positions[k] - history.positions[k - 1]) / dt).squaredNorm();
        ++velocities;
        periods.push_back(dt);
      }
    }
  }
  MotionNormalisation normalisation;
  if (velocities > 0) normalisation.speed = std::max(0.1, std::sqrt(speed_squares / static_cast<double>(velocities)));
  if (!periods.empty()) {
    std::sort(periods.begin(), periods.end());
    normalisation.period = periods[periods.size() / 2];
    normalisation.longest_interval = periods[(periods.size() - 1) * 99 / 100];
  }
  return normalisation;
}

double constant_velocity_error(const std::vector<TrainingGraph>& graphs) {
  double total = 0.0;
  std::size_t objects = 0;
  for (const TrainingGraph& graph : graphs) {
    for (std::size_t i = 0; i < graph.graph.objects.size(); ++i) {
      const ObjectHistory& history = graph.graph.objects[i];
      const std::size_t n = history.positions.size();
      Vector3d velocity = Vector3d::Zero();
      if (n >= 2) velocity = (history.positions[n - 1] - history.positions[n - 2]) / (history.times[n - 1] - history.times[n - 2]);
      const Vector3d predicted = history.positions.back() + velocity * (graph.graph.target_time - history.times.back());
      total += (predicted - graph.targets[i]).norm();
      ++objects;
    }
  }
  return objects == 0 ? 0.0 : total / static_cast<double>(objects);
}

TrainingReport train_motion_model(const std::vector<TrainingGraph>& train, const std::vector<TrainingGraph>& validation,
                                  const MotionTrainingOptions& options, const std::string& model_path,
                                  const std::function<void(const TrainingProgress&)>& progress) {
  if (options.epochs < 1) throw std::invalid_argument("--epochs must be at least 1");
  if (options.batch_graphs < 1) throw std::invalid_argument("--batch must be at least 1");
  if (!(options.learning_rate > 0.0)) throw std::invalid_argument("--lr must be > 0");
  check_graphs(train, "training");
  check_graphs(validation, "validation");
  torch::set_num_threads(options.threads > 0 ? options.threads
                                             : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));

  MotionNormalisation normalisation = measure_normalisation(train);
  if (options.frame_period > 0.0) normalisation.frame_period = options.frame_period;
  MotionModel model = options.resume.empty() ? MotionModel(options.shape, normalisation, options.seed)
                                             : MotionModel::load(options.resume);
  MotionModel::Impl& impl = model.impl();
  impl.weights_float16 = options.weights_float16;
  torch::optim::Adam optimizer(impl.network->parameters(), torch::optim::AdamOptions(options.learning_rate));
  int first_epoch = 1;
  std::error_code ignored_error;
  double best_error = std::numeric_limits<double>::infinity();
  bool resumed_without_optimizer_state = false;
  if (!options.resume.empty()) {
    // The resumed file is the best model so far: it is the output until an epoch beats it.
    if (!std::filesystem::equivalent(options.resume, model_path, ignored_error)) {
      std::filesystem::copy_file(options.resume, model_path, std::filesystem::copy_options::overwrite_existing);
    }
    resumed_without_optimizer_state = !load_optimizer_state(options.resume, optimizer);
    const nlohmann::json& stored = impl.metadata;
    first_epoch = stored.value("epoch", 0) + 1;
  }

  TrainingReport report;
  report.resumed_without_optimizer_state = resumed_without_optimizer_state;
  report.train_objects = count_objects(train);
  report.validation_objects = count_objects(validation);
  report.constant_velocity_validation_error = constant_velocity_error(validation);

  // Validation batches are fixed; so are each object's P_last + P_target (in validation order), their
  // mean and the reference period for Q.
  std::vector<std::vector<const TrainingGraph*>> validation_batches;
  std::vector<Matrix3d> known_covariances;
  known_covariances.reserve(report.validation_objects);
  Matrix3d mean_known_covariance = Matrix3d::Zero();
  std::vector<double> horizons;
  for (std::size_t g = 0; g < validation.size(); ++g) {
    if (g % kValidationBatchGraphs == 0) validation_batches.emplace_back();
    validation_batches.back().push_back(&validation[g]);
    const TrainingGraph& graph = validation[g];
    for (std::size_t i = 0; i < graph.targets.size(); ++i) {
      const Matrix3d& last = graph.history_covariances[i].back();
      mean_known_covariance += last;
      if (graph.target_covariances.empty()) {
        known_covariances.push_back(last);
      } else {
        mean_known_covariance += graph.target_covariances[i];
        known_covariances.push_back(last + graph.target_covariances[i]);
      }
      horizons.push_back(graph.graph.target_time - graph.graph.objects[i].times.back());
    }
  }
  mean_known_covariance /= static_cast<double>(report.validation_objects);
  std::nth_element(horizons.begin(), horizons.begin() + static_cast<std::ptrdiff_t>(horizons.size() / 2), horizons.end());
  const double reference_period = horizons[horizons.size() / 2];

  // Validation: the mean Euclidean error, Q_ref calibrated from the residuals' second moment, and the
  // mean negative log-likelihood of the targets under N(x̂, P_last + P_target + Q_ref).
  struct Validation {
    double error = 0.0;
    double nll = 0.0;
    Matrix3d process_noise = Matrix3d::Zero();
  };
  const auto validate = [&] {
    torch::NoGradGuard no_grad;
    impl.network->eval();
    Validation result;
    Matrix3d residual_moment = Matrix3d::Zero();
    std::vector<Vector3d> residuals;
    residuals.reserve(report.validation_objects);
    for (const auto& chosen : validation_batches) {
      const std::vector<MotionGraph> graphs = graphs_of(chosen);
      const detail::MotionBatch batch = detail::make_motion_batch(graphs, impl.shape, impl.normalisation);
      const std::vector<std::vector<Vector3d>> predicted =
          impl.positions_from(batch, impl.network->forward(batch));
      for (std::size_t g = 0; g < chosen.size(); ++g) {
        const TrainingGraph& graph = *chosen[g];
        for (std::size_t i = 0; i < graph.targets.size(); ++i) {
          const Vector3d residual = graph.targets[i] - predicted[g][i];
          result.error += residual.norm();
          residual_moment += residual * residual.transpose();
          residuals.push_back(residual);
        }
      }
    }
    const auto n = static_cast<double>(report.validation_objects);
    result.error /= n;
    result.process_noise = calibrated_process_noise(residual_moment / n, mean_known_covariance);
    if (options.rotate) result.process_noise = averaged_over_headings(result.process_noise);
    for (std::size_t k = 0; k < residuals.size(); ++k) {
      const Eigen::LDLT<Matrix3d> covariance(known_covariances[k] + result.process_noise);
      result.nll += 0.5 * (residuals[k].dot(covariance.solve(residuals[k])) +
                           covariance.vectorD().array().log().sum() + 3.0 * std::log(2.0 * std::numbers::pi));
    }
    result.nll /= n;
    return result;
  };
  // Writes the model as the best so far, with what `validated` measured of it.
  const auto keep_as_best = [&](int epoch, const Validation& validated) {
    best_error = validated.error;
    impl.process_noise_reference = validated.process_noise;
    impl.process_noise_period = reference_period;
    nlohmann::json metadata = options.metadata;
    metadata["epoch"] = epoch;
    metadata["best_validation_error"] = best_error;
    metadata["constant_velocity_validation_error"] = report.constant_velocity_validation_error;
    metadata["learning_rate"] = options.learning_rate;
    metadata["batch_graphs"] = options.batch_graphs;
    metadata["seed"] = options.seed;
    metadata["threads"] = torch::get_num_threads();  // weights are bitwise reproducible for the same count
    // ... and the same kernels: LibTorch's and OpenBLAS's, chosen by the CPU unless pinned
    // (stgf train --portable pins them to ATEN_CPU_CAPABILITY=default, OPENBLAS_CORETYPE=Prescott).
    for (const char* variable : {"ATEN_CPU_CAPABILITY", "OPENBLAS_CORETYPE"}) {
      const char* value = std::getenv(variable);
      metadata["kernels"][variable] = value != nullptr ? value : "chosen by the CPU";
    }
    metadata["history_noise"] = options.history == HistoryNoise::kObserved ? "observed" : "truth_with_matched_noise";
    impl.metadata = metadata;
    impl.save(model_path, metadata, options.keep_optimizer_state ? &optimizer : nullptr);
    report.best_epoch = epoch;
    report.process_noise = impl.process_noise_reference;
    report.process_noise_period = reference_period;
  };
  if (options.resume.empty()) {
    report.initial_validation_nll = validate().nll;
  } else {
    // The resumed model is the best so far as it does on THIS validation split: the best error stored
    // in it may be another benchmark's (a model resumed to fine-tune it on other data), a bar no epoch
    // need pass, and its metadata (the registration prior, the benchmark) that benchmark's.
    const Validation resumed = validate();
    report.resumed_validation_error = resumed.error;
    if (std::isfinite(resumed.error)) keep_as_best(first_epoch - 1, resumed);
  }

  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  std::vector<std::size_t> order(train.size());
  std::iota(order.begin(), order.end(), 0);
  const int batches = static_cast<int>((train.size() + static_cast<std::size_t>(options.batch_graphs) - 1) /
                                       static_cast<std::size_t>(options.batch_graphs));
  for (int epoch = first_epoch; epoch < first_epoch + options.epochs; ++epoch) {
    const double epoch_start = elapsed();
    std::mt19937_64 random(options.seed * 1000003ULL + static_cast<std::uint64_t>(epoch));
    std::shuffle(order.begin(), order.end(), random);
    impl.network->train();
    double loss_sum = 0.0;
    for (int b = 0; b < batches; ++b) {
      std::vector<TrainingGraph> noisy;
      std::vector<const TrainingGraph*> chosen;
      const std::size_t begin = static_cast<std::size_t>(b) * static_cast<std::size_t>(options.batch_graphs);
      const std::size_t end = std::min(order.size(), begin + static_cast<std::size_t>(options.batch_graphs));
      if (options.history == HistoryNoise::kTruthWithMatchedNoise || options.rotate) {
        noisy.reserve(end - begin);
        std::uniform_real_distribution<double> heading(0.0, 2.0 * std::numbers::pi);
        for (std::size_t k = begin; k < end; ++k) {
          TrainingGraph graph = options.history == HistoryNoise::kTruthWithMatchedNoise
                                    ? with_matched_noise(train[order[k]], random)
                                    : train[order[k]];
          noisy.push_back(options.rotate ? rotated(std::move(graph), heading(random)) : std::move(graph));
        }
        for (const TrainingGraph& graph : noisy) chosen.push_back(&graph);
      } else {
        for (std::size_t k = begin; k < end; ++k) chosen.push_back(&train[order[k]]);
      }
      const std::vector<MotionGraph> graphs = graphs_of(chosen);
      const detail::MotionBatch batch = detail::make_motion_batch(graphs, impl.shape, impl.normalisation);
      if (batch.last_positions.empty()) continue;
      const Targets targets = targets_of(chosen, batch);
      optimizer.zero_grad();
      const torch::Tensor loss = euclidean_errors(impl.network->forward(batch), impl.normalisation, targets).mean();
      const double loss_value = loss.item<double>();
      if (!std::isfinite(loss_value)) {
        report.diverged_epoch = epoch;
        report.diverged_batch = b + 1;
        break;
      }
      loss.backward();
      optimizer.step();
      loss_sum += loss_value;
      if (progress) {
        TrainingProgress p{epoch, first_epoch + options.epochs - 1, b + 1, batches, loss_sum / (b + 1), elapsed(), nullptr};
        progress(p);
      }
    }

    if (report.diverged_epoch != 0) break;

    const Validation validated = validate();
    EpochReport epoch_report{epoch, loss_sum / std::max(1, batches), validated.error, validated.nll,
                             elapsed() - epoch_start};
    if (!std::isfinite(epoch_report.validation_error)) {
      report.diverged_epoch = epoch;
      report.diverged_batch = 0;
      break;
    }
    report.epochs.push_back(epoch_report);
    if (epoch_report.validation_error < best_error) keep_as_best(epoch, validated);
    if (progress) {
      TrainingProgress p{epoch, first_epoch + options.epochs - 1, batches, batches, epoch_report.train_loss, elapsed(),
                         &report.epochs.back()};
      progress(p);
    }
  }
  report.best_validation_error = best_error;
  return report;
}

void save_recalibrated_model(const MotionModel& model, const std::string& path, const nlohmann::json& metadata) {
  const MotionModel::Impl& impl = model.impl();
  torch::optim::Adam optimizer(impl.network->parameters(),
                               torch::optim::AdamOptions(metadata.value("learning_rate", 1e-3)));
  const bool has_optimizer = load_optimizer_state(path, optimizer);
  impl.save(path, metadata, has_optimizer ? &optimizer : nullptr);
}

}  // namespace stgf
