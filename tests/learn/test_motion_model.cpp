// SPDX-License-Identifier: Apache-2.0
// The learned motion model Φ on tiny shapes: ragged batches, gradients, save → load, training
// lowers the loss, Φ beats constant velocity on turning motion, bad model files give clear errors.

#include "stgf/learn/motion_model.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "stgf/io/input_error.hpp"
#include "stgf/learn/motion_network.hpp"
#include "stgf/learn/motion_training.hpp"
#include "support/scratch_directory.hpp"
#include "support/tiny_motion_model.hpp"

namespace stgf {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using stgf::testing::tiny_shape;

// An object on a circle of radius r around c, angular speed ω, phase φ, sampled at `times`.
ObjectHistory circling(const std::string& id, const Vector3d& centre, double radius, double omega, double phase,
                       const std::vector<double>& times) {
  ObjectHistory history{id, {}, {}};
  for (double t : times) {
    history.positions.push_back(centre + radius * Vector3d(std::cos(phase + omega * t), std::sin(phase + omega * t), 0));
    history.times.push_back(t);
  }
  return history;
}

// Graphs of objects turning on circles (no noise): what constant velocity gets wrong.
std::vector<TrainingGraph> turning_graphs(int count, std::uint64_t seed, double dt = 0.4) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<TrainingGraph> graphs;
  for (int g = 0; g < count; ++g) {
    TrainingGraph training;
    const int objects = 1 + g % 3;
    const double start = 10.0 * uniform(random);
    std::vector<double> times;
    for (int k = 0; k < 5; ++k) times.push_back(start + k * dt);
    training.graph.scene = "s" + std::to_string(g);
    training.graph.target_time = start + 5 * dt;
    for (int i = 0; i < objects; ++i) {
      const Vector3d centre(20.0 * uniform(random), 20.0 * uniform(random), 0.0);
      const double radius = 2.0 + 2.0 * uniform(random);
      const double omega = (uniform(random) < 0.5 ? -1.0 : 1.0) * (0.4 + 0.4 * uniform(random));
      const double phase = 6.28 * uniform(random);
      ObjectHistory history = circling("o" + std::to_string(i), centre, radius, omega, phase, times);
      training.targets.push_back(circling("", centre, radius, omega, phase, {training.graph.target_time}).positions[0]);
      training.true_histories.push_back(history.positions);
      training.history_covariances.emplace_back(history.positions.size(), 1e-4 * Matrix3d::Identity());
      training.graph.objects.push_back(std::move(history));
    }
    graphs.push_back(std::move(training));
  }
  return graphs;
}

std::vector<MotionGraph> graphs_only(const std::vector<TrainingGraph>& graphs) {
  std::vector<MotionGraph> result;
  for (const TrainingGraph& graph : graphs) result.push_back(graph.graph);
  return result;
}

fs::path scratch(const std::string& name) {
  return fs::temp_directory_path() / ("stgf-test-learn-" + std::to_string(::getpid()) + "-" + name);
}

TEST(MotionModel, RaggedBatchesGiveOnePredictionPerObject) {
  const MotionModel model(tiny_shape(), MotionNormalisation{}, 1);
  std::vector<MotionGraph> graphs;
  for (int objects : {1, 3, 7}) {
    MotionGraph graph{"s", "v", 10.0, {}};
    for (int i = 0; i < objects; ++i) {
      std::vector<double> times;
      for (int k = 0; k < 1 + (i % 6); ++k) times.push_back(9.0 - k * 0.1);
      std::reverse(times.begin(), times.end());
      graph.objects.push_back(circling("o" + std::to_string(i), Vector3d(i, 0, 0), 1.0, 0.5, 0.0, times));
    }
    graphs.push_back(graph);
  }
  const auto predicted = model.predict(graphs);
  ASSERT_EQ(predicted.size(), 3u);
  EXPECT_EQ(predicted[0].size(), 1u);
  EXPECT_EQ(predicted[1].size(), 3u);
  EXPECT_EQ(predicted[2].size(), 7u);
  for (const auto& graph : predicted) {
    for (const Vector3d& p : graph) EXPECT_TRUE(p.allFinite());
  }
  // Edges: 3 objects fully connected (9), 7 objects by 2 nearest plus self (21), 1 object (1).
  const detail::MotionBatch batch = detail::make_motion_batch(graphs, tiny_shape(), MotionNormalisation{});
  EXPECT_EQ(batch.tensors.edge_source.size(0), 1 + 9 + 21);
  EXPECT_EQ(batch.tensors.motion.sizes(), (std::vector<int64_t>{11, 4, 7}));
}

TEST(MotionModel, GradientsReachEveryParameter) {
  MotionModel model(tiny_shape(), MotionNormalisation{}, 2);
  const std::vector<TrainingGraph> graphs = turning_graphs(8, 3);
  const std::vector<MotionGraph> inputs = graphs_only(graphs);
  const detail::MotionBatch batch = detail::make_motion_batch(inputs, model.shape(), model.normalisation());
  model.impl().network->train();
  const torch::Tensor velocity = model.impl().network->forward(batch);
  velocity.pow(2).sum().backward();
  for (const auto& parameter : model.impl().network->named_parameters()) {
    ASSERT_TRUE(parameter.value().grad().defined()) << parameter.key();
    EXPECT_GT(parameter.value().grad().abs().sum().item<double>(), 0.0) << parameter.key();
  }
}

// A small model with a stated Q (kQ at 0.4 s), saved to `path`: trained (so to say) on data whose
// intervals have a median of 0.4 s and whose fastest benchmark runs at 0.25 s.
const Matrix3d kQ = (Matrix3d() << 0.02, 0.001, 0, 0.001, 0.03, 0, 0, 0, 0.01).finished();
MotionModel saved_model(std::uint64_t seed, const std::string& path) {
  MotionModel model(tiny_shape(), MotionNormalisation{1.3, 0.4, 5.0, 1.2, 0.25}, seed);
  model.set_process_noise(kQ, 0.4);
  model.save(path, {{"input", "fused"}});
  return model;
}

TEST(MotionModel, SaveThenLoadGivesIdenticalPredictions) {
  const std::string path = scratch("model.pt").string();
  const MotionModel model = saved_model(4, path);
  const Matrix3d& q = kQ;
  const MotionModel loaded = MotionModel::load(path);
  fs::remove(path);
  const std::vector<MotionGraph> graphs = graphs_only(turning_graphs(5, 5));
  const auto a = model.predict(graphs);
  const auto b = loaded.predict(graphs);
  for (std::size_t g = 0; g < a.size(); ++g) {
    for (std::size_t i = 0; i < a[g].size(); ++i) EXPECT_EQ(a[g][i], b[g][i]);
  }
  EXPECT_EQ(loaded.process_noise(0.4), q);
  EXPECT_LT((loaded.process_noise(0.8) - 4.0 * q).norm(), 1e-15);
  EXPECT_EQ(loaded.metadata().value("input", ""), "fused");
  EXPECT_EQ(loaded.normalisation().speed, 1.3);
  EXPECT_EQ(loaded.normalisation().longest_interval, 1.2);
  EXPECT_EQ(loaded.prediction_horizon(), kHorizonFactor * 1.2);
  EXPECT_EQ(loaded.normalisation().frame_period, 0.25);
  EXPECT_EQ(loaded.history_spacing(), kHistorySpacingFactor * 0.25);  // the fastest data's, not s_t's
  EXPECT_EQ(loaded.shape().hidden, 8);
}

// The model file read without LibTorch (model/trained_motion_model.hpp) is the model LibTorch reads
// and the model that wrote it: the same settings and, bit for bit, the same forecasts.
TEST(TrainedMotionModel, IsTheSavedModelBitForBit) {
  const std::string path = scratch("trained.pt").string();
  const MotionModel model = saved_model(11, path);
  const TrainedMotionModel trained = TrainedMotionModel::load(path);
  const MotionModel loaded = MotionModel::load(path);
  fs::remove(path);
  const std::vector<MotionGraph> graphs = graphs_only(turning_graphs(6, 5));
  const auto expected = model.forecast(graphs);
  for (const auto& forecasts : {trained.forecast(graphs), loaded.forecast(graphs), model.trained().forecast(graphs)}) {
    ASSERT_EQ(forecasts.size(), expected.size());
    for (std::size_t g = 0; g < expected.size(); ++g) {
      ASSERT_EQ(forecasts[g].size(), expected[g].size());
      for (std::size_t i = 0; i < expected[g].size(); ++i) {
        EXPECT_EQ(forecasts[g][i].acceleration, expected[g][i].acceleration);
        EXPECT_EQ(forecasts[g][i].velocity, expected[g][i].velocity);
      }
    }
  }
  EXPECT_EQ(trained.process_noise(0.8), loaded.process_noise(0.8));
  EXPECT_EQ(trained.prediction_horizon(), loaded.prediction_horizon());
  EXPECT_EQ(trained.history_spacing(), loaded.history_spacing());
  EXPECT_EQ(trained.history_spacing(), kHistorySpacingFactor * 0.25);
  EXPECT_EQ(trained.history_positions(), loaded.history_positions());
  EXPECT_EQ(trained.metadata(), loaded.metadata());
}

// The LibTorch-free reader's list of the network's weights is the network's own, in its order (the
// checksum runs over them in that order).
TEST(TrainedMotionModel, KnowsTheNetworksParametersInOrder) {
  for (const MotionModelShape& shape : {tiny_shape(), MotionModelShape{}}) {
    const MotionModel model(shape, MotionNormalisation{}, 1);
    const auto parameters = model.impl().network->named_parameters();
    const std::vector<MotionNetworkParameter> listed = motion_network_parameters(shape);
    ASSERT_EQ(listed.size(), parameters.size());
    for (std::size_t k = 0; k < listed.size(); ++k) {
      EXPECT_EQ(listed[k].name, parameters[k].key());
      EXPECT_EQ(listed[k].sizes, parameters[k].value().sizes().vec()) << listed[k].name;
    }
  }
}

// The fixture of the LibTorch-free tests (tests/model/data) reads the same with LibTorch.
TEST(TrainedMotionModel, TheFixtureReadsTheSameWithLibTorch) {
  const std::string path = std::string(STGF_SOURCE_DIR) + "/tests/model/data/tiny-motion-model.pt";
  const TrainedMotionModel trained = TrainedMotionModel::load(path);
  const MotionModel loaded = MotionModel::load(path);
  const std::vector<MotionGraph> graphs = graphs_only(turning_graphs(4, 5));
  const auto a = trained.forecast(graphs);
  const auto b = loaded.forecast(graphs);
  for (std::size_t g = 0; g < a.size(); ++g) {
    for (std::size_t i = 0; i < a[g].size(); ++i) EXPECT_EQ(a[g][i].acceleration, b[g][i].acceleration);
  }
}

// The step period is the median training interval; the horizon's base, the 99th percentile, so one
// long gap in the training data does not stretch it.
TEST(MotionModel, NormalisationMeasuresPeriodAndLongestInterval) {
  ObjectHistory history{"o", {Vector3d::Zero()}, {0.0}};
  for (int k = 0; k < 101; ++k) {
    const double dt = k < 50 ? 0.1 : k < 100 ? 0.3 : 10.0;
    history.times.push_back(history.times.back() + dt);
    history.positions.push_back(history.positions.back() + Vector3d(dt, 0, 0));  // 1 m/s
  }
  const std::vector<TrainingGraph> graphs = {TrainingGraph{MotionGraph{"s", "", history.times.back() + 0.1, {history}}}};
  const MotionNormalisation normalisation = measure_normalisation(graphs);
  EXPECT_NEAR(normalisation.speed, 1.0, 1e-9);
  EXPECT_NEAR(normalisation.period, 0.3, 1e-9);
  EXPECT_NEAR(normalisation.longest_interval, 0.3, 1e-9);
}

TEST(MotionModel, BadModelFilesGiveClearErrors) {
  const auto error_of = [](const std::string& path) {
    try {
      MotionModel::load(path);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error_of("/nonexistent/model.pt"), HasSubstr("/nonexistent/model.pt: no such model file"));
  const std::string garbage = scratch("garbage.pt").string();
  std::ofstream(garbage) << "this is not a model";
  EXPECT_THAT(error_of(garbage), HasSubstr(garbage + ": not a readable model file"));
  fs::remove(garbage);

  // A valid file cut short.
  const std::string path = scratch("whole.pt").string();
  MotionModel(tiny_shape(), MotionNormalisation{}, 6).save(path);
  const auto size = fs::file_size(path);
  fs::resize_file(path, size / 2);
  EXPECT_THAT(error_of(path), HasSubstr(path + ": "));
  fs::remove(path);

  // A torch archive that is not a stgf model.
  const std::string foreign = scratch("foreign.pt").string();
  torch::serialize::OutputArchive archive;
  archive.write("weights", torch::ones({3}));
  archive.save_to(foreign);
  EXPECT_THAT(error_of(foreign), HasSubstr("not a stgf motion model"));
  fs::remove(foreign);

  // Weights that do not match the stated shape: a model's network saved under another model's config.
  const std::string mismatched = scratch("mismatched.pt").string();
  MotionModelShape wider = tiny_shape();
  wider.hidden = 12;
  MotionModel other(wider, MotionNormalisation{}, 7);
  torch::serialize::OutputArchive mixed;
  mixed.write("format", c10::IValue(std::string("stgf-motion-model")));
  mixed.write("version", c10::IValue(static_cast<int64_t>(1)));
  const std::string good = scratch("good.pt").string();
  MotionModel(tiny_shape(), MotionNormalisation{}, 8).save(good);
  torch::serialize::InputArchive good_archive;
  good_archive.load_from(good);
  c10::IValue config;
  good_archive.read("config", config);
  mixed.write("config", config);
  torch::serialize::OutputArchive network;
  other.impl().network->save(network);
  mixed.write("network", network);
  mixed.save_to(mismatched);
  EXPECT_THAT(error_of(mismatched), HasSubstr("do not match its stated shape"));
  fs::remove(mismatched);
  fs::remove(good);
}

// Enough capacity and epochs to learn turning on a few hundred graphs in about a second.
MotionTrainingOptions turning_training_options() {
  MotionTrainingOptions options;
  options.shape = tiny_shape();
  options.shape.hidden = 16;
  options.shape.attention_hidden = 8;
  options.epochs = 25;
  options.batch_graphs = 16;
  options.learning_rate = 5e-3;
  options.threads = 1;
  return options;
}

TEST(MotionTraining, LossFallsAndPhiBeatsConstantVelocityOnTurningMotion) {
  const std::vector<TrainingGraph> train = turning_graphs(300, 11);
  const std::vector<TrainingGraph> validation = turning_graphs(60, 12);
  const MotionTrainingOptions options = turning_training_options();
  const std::string path = scratch("trained.pt").string();
  const TrainingReport report = train_motion_model(train, validation, options, path);
  ASSERT_EQ(report.epochs.size(), 25u);
  EXPECT_LT(report.epochs.back().train_loss, 0.5 * report.epochs.front().train_loss);
  EXPECT_LT(report.best_validation_error, report.constant_velocity_validation_error);
  // The file holds the best epoch, with a calibrated Q.
  const MotionModel best = MotionModel::load(path);
  EXPECT_EQ(best.metadata().value("epoch", 0), report.best_epoch);
  EXPECT_GT(best.process_noise(0.4).trace(), 0.0);
  fs::remove(path);
}

// Φ works in per-second units: trained at one rate (2.5 Hz), it still beats constant velocity at
// 5 Hz and at 1.25 Hz, which it never saw.
TEST(MotionTraining, TrainedAtOneRateWorksAtOthers) {
  const MotionTrainingOptions options = turning_training_options();
  const std::string path = scratch("rate.pt").string();
  train_motion_model(turning_graphs(300, 31, 0.4), turning_graphs(60, 32, 0.4), options, path);
  const MotionModel model = MotionModel::load(path);
  fs::remove(path);
  for (double dt : {0.2, 0.8}) {
    const std::vector<TrainingGraph> graphs = turning_graphs(100, 33, dt);
    const auto predicted = model.predict(graphs_only(graphs));
    double error = 0.0;
    std::size_t objects = 0;
    for (std::size_t g = 0; g < graphs.size(); ++g) {
      for (std::size_t i = 0; i < graphs[g].targets.size(); ++i, ++objects) {
        error += (predicted[g][i] - graphs[g].targets[i]).norm();
      }
    }
    EXPECT_LT(error / objects, constant_velocity_error(graphs)) << "Δt = " << dt;
  }
}

// What a recording without truth gives: every position measured with noise σ = 5 cm (histories and
// targets), target covariances σ² I, no true histories.
std::vector<TrainingGraph> measured(std::vector<TrainingGraph> graphs, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::normal_distribution<double> noise(0.0, 0.05);
  const Matrix3d r = 0.05 * 0.05 * Matrix3d::Identity();
  const auto noisy = [&](const Vector3d& p) { return Vector3d(p + Vector3d(noise(random), noise(random), noise(random))); };
  for (TrainingGraph& graph : graphs) {
    graph.true_histories.clear();
    graph.target_covariances.assign(graph.targets.size(), r);
    for (std::size_t i = 0; i < graph.targets.size(); ++i) {
      for (Vector3d& p : graph.graph.objects[i].positions) p = noisy(p);
      graph.history_covariances[i].assign(graph.graph.objects[i].positions.size(), r);
      graph.targets[i] = noisy(graph.targets[i]);
    }
  }
  return graphs;
}

// Trained towards noisy measurements alone, Φ still learns the turning: the validation NLL of the
// measured targets falls below the untrained model's, and against the truth it beats constant velocity.
TEST(MotionTraining, WithoutTruthLearnsFromTheMeasurementsAlone) {
  const std::vector<TrainingGraph> validation_truth = turning_graphs(60, 42);
  const std::vector<TrainingGraph> train = measured(turning_graphs(300, 41), 43);
  const std::vector<TrainingGraph> validation = measured(validation_truth, 44);
  const std::string path = scratch("measured.pt").string();
  const TrainingReport report = train_motion_model(train, validation, turning_training_options(), path);
  ASSERT_TRUE(report.initial_validation_nll.has_value());
  EXPECT_LT(report.epochs.back().validation_nll, *report.initial_validation_nll - 1.0)
      << report.epochs.back().validation_nll << " against " << *report.initial_validation_nll;
  const MotionModel model = MotionModel::load(path);
  fs::remove(path);
  const auto predicted = model.predict(graphs_only(validation));  // from the noisy histories
  double error = 0.0;
  std::size_t objects = 0;
  for (std::size_t g = 0; g < validation.size(); ++g) {
    for (std::size_t i = 0; i < validation[g].targets.size(); ++i, ++objects) {
      error += (predicted[g][i] - validation_truth[g].targets[i]).norm();
    }
  }
  std::vector<TrainingGraph> noisy_histories_true_targets = validation;
  for (std::size_t g = 0; g < validation.size(); ++g) noisy_histories_true_targets[g].targets = validation_truth[g].targets;
  EXPECT_LT(error / objects, constant_velocity_error(noisy_histories_true_targets));
  // Histories drawn around the truth need the truth.
  MotionTrainingOptions matched = turning_training_options();
  matched.epochs = 1;
  matched.history = HistoryNoise::kTruthWithMatchedNoise;
  EXPECT_THROW(train_motion_model(train, validation, matched, path), std::invalid_argument);
  fs::remove(path);
}

TEST(MotionTraining, SameSeedSameModel) {
  const std::vector<TrainingGraph> train = turning_graphs(40, 21);
  const std::vector<TrainingGraph> validation = turning_graphs(10, 22);
  MotionTrainingOptions options;
  options.shape = tiny_shape();
  options.epochs = 2;
  options.batch_graphs = 8;
  options.threads = 1;
  options.seed = 9;
  const std::string a = scratch("a.pt").string(), b = scratch("b.pt").string();
  train_motion_model(train, validation, options, a);
  train_motion_model(train, validation, options, b);
  const std::vector<MotionGraph> graphs = graphs_only(validation);
  const auto pa = MotionModel::load(a).predict(graphs);
  const auto pb = MotionModel::load(b).predict(graphs);
  for (std::size_t g = 0; g < pa.size(); ++g) {
    for (std::size_t i = 0; i < pa[g].size(); ++i) EXPECT_EQ(pa[g][i], pb[g][i]);
  }
  // The files themselves, optimizer state included, are byte-identical.
  EXPECT_TRUE(testing::file_bytes(a) == testing::file_bytes(b)) << "same seed, different model file bytes";
  fs::remove(a);
  fs::remove(b);
}

// A model stored with float16 weights (stgf train --weights float16): about half the file of the same
// training stored as float32; its weights are the float32 ones rounded to float16; LibTorch, the
// LibTorch-free reader and the trained model in memory all run those rounded weights, bit for bit;
// saving it again (Q recalibrated) keeps them float16; and training resumes from it.
TEST(MotionTraining, Float16WeightsAreHalfTheFileAndTheSameModelEverywhere) {
  const std::vector<TrainingGraph> train = turning_graphs(40, 21);
  const std::vector<TrainingGraph> validation = turning_graphs(10, 22);
  MotionTrainingOptions options;
  options.shape = tiny_shape();
  options.shape.hidden = 32;  // enough weights for the file's size to be mostly theirs
  options.epochs = 2;
  options.batch_graphs = 8;
  options.threads = 1;
  options.seed = 9;
  options.keep_optimizer_state = false;
  const std::string full = scratch("full.pt").string(), half = scratch("half.pt").string();
  train_motion_model(train, validation, options, full);
  options.weights_float16 = true;
  train_motion_model(train, validation, options, half);
  const std::uintmax_t full_size = fs::file_size(full), half_size = fs::file_size(half);
  EXPECT_LT(static_cast<double>(half_size), 0.7 * static_cast<double>(full_size)) << full_size << " → " << half_size;

  const MotionModel full_loaded = MotionModel::load(full);
  const MotionModel half_loaded = MotionModel::load(half);
  const auto full_weights = full_loaded.impl().network->parameters();
  const auto half_weights = half_loaded.impl().network->parameters();
  ASSERT_EQ(full_weights.size(), half_weights.size());
  double largest_change = 0.0;
  for (std::size_t k = 0; k < full_weights.size(); ++k) {
    EXPECT_EQ(half_weights[k].scalar_type(), torch::kFloat32);  // run in float32
    EXPECT_TRUE(torch::equal(half_weights[k], full_weights[k].to(torch::kHalf).to(torch::kFloat32))) << k;
    largest_change = std::max(largest_change, (half_weights[k] - full_weights[k]).abs().max().item<double>());
  }
  EXPECT_GT(largest_change, 0.0);  // the rounding did happen

  const std::vector<MotionGraph> graphs = graphs_only(validation);
  const auto expected = TrainedMotionModel::load(half).forecast(graphs);
  for (const auto& forecasts : {half_loaded.forecast(graphs), half_loaded.trained().forecast(graphs)}) {
    for (std::size_t g = 0; g < expected.size(); ++g) {
      for (std::size_t i = 0; i < expected[g].size(); ++i) EXPECT_EQ(forecasts[g][i].velocity, expected[g][i].velocity);
    }
  }

  const std::string again = scratch("again.pt").string();
  fs::copy_file(half, again);
  save_recalibrated_model(half_loaded, again, half_loaded.metadata());
  EXPECT_LT(fs::file_size(again), fs::file_size(full));
  const auto again_weights = MotionModel::load(again).impl().network->parameters();
  for (std::size_t k = 0; k < half_weights.size(); ++k) EXPECT_TRUE(torch::equal(again_weights[k], half_weights[k])) << k;

  options.resume = half;
  options.epochs = 1;
  const std::string resumed = scratch("resumed.pt").string();
  EXPECT_NO_THROW(train_motion_model(train, validation, options, resumed));
  EXPECT_TRUE(std::isfinite(MotionModel::load(resumed).predict(graphs)[0][0].x()));
  for (const std::string& path : {full, half, again, resumed}) fs::remove(path);
}

// The largest stored record of a zip archive (a PyTorch archive stores records uncompressed): its
// offset and size in the file, from the central directory (PK\1\2 entries: size at +20, name,
// extra and comment lengths at +28, +30, +32, the local header's offset at +42).
std::pair<std::size_t, std::size_t> largest_zip_record(const std::string& bytes, const std::string& name_part = "") {
  std::pair<std::size_t, std::size_t> largest{0, 0};
  const auto u16 = [&](std::size_t at) { return static_cast<std::size_t>(static_cast<unsigned char>(bytes[at])) |
                                               static_cast<std::size_t>(static_cast<unsigned char>(bytes[at + 1])) << 8; };
  const auto u32 = [&](std::size_t at) { return u16(at) | u16(at + 2) << 16; };
  for (std::size_t at = bytes.find("PK\x01\x02"); at != std::string::npos && at + 46 <= bytes.size();
       at = bytes.find("PK\x01\x02", at + 46)) {
    const std::size_t size = u32(at + 20);
    const std::size_t local = u32(at + 42);
    if (bytes.substr(at + 46, u16(at + 28)).find(name_part) == std::string::npos) continue;
    const std::size_t data = local + 30 + u16(local + 26) + u16(local + 28);
    if (size > largest.second) largest = {data, size};
  }
  return largest;
}

// Found by fuzz_model_file: damaged TorchScript code inside the archive made LibTorch throw a parse
// error that is not a c10::Error, and it escaped as a non-input error.
TEST(MotionModel, DamagedArchiveCodeIsAnInputError) {
  const std::string path = scratch("code.pt").string();
  MotionModel(tiny_shape(), MotionNormalisation{}, 6).save(path);
  std::string bytes = testing::file_bytes(path);
  const auto [offset, size] = largest_zip_record(bytes, ".py");
  ASSERT_GT(size, 16u) << "no TorchScript code record found";
  for (std::size_t k = offset; k < offset + 8; ++k) bytes[k] = static_cast<char>(0xb7);
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
  try {
    MotionModel::load(path);
    ADD_FAILURE() << "damaged code was accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path + ": not a readable model file")) << error.what();
    EXPECT_THAT(error.what(), HasSubstr("fails its CRC-32")) << error.what();
  }
  fs::remove(path);
}

TEST(MotionModel, CorruptWeightsAreCaughtByTheChecksum) {
  const std::string path = scratch("intact.pt").string();
  MotionModel(tiny_shape(), MotionNormalisation{}, 6).save(path);
  const std::string bytes = testing::file_bytes(path);
  const auto [offset, size] = largest_zip_record(bytes);
  ASSERT_GT(size, 256u) << "no weight record found";
  for (const std::size_t start : {offset, offset + size / 2, offset + size - 64}) {
    std::string corrupt = bytes;
    for (std::size_t k = start; k < start + 64; ++k) corrupt[k] = static_cast<char>(corrupt[k] ^ 0x5a);
    const std::string corrupt_path = scratch("corrupt.pt").string();
    std::ofstream(corrupt_path, std::ios::binary) << corrupt;
    try {
      MotionModel::load(corrupt_path);
      ADD_FAILURE() << "64 flipped bytes at " << start << " were accepted";
    } catch (const InputError& error) {
      EXPECT_THAT(error.what(), HasSubstr(corrupt_path + ": ")) << error.what();
    }
    fs::remove(corrupt_path);
  }
  fs::remove(path);
}

}  // namespace
}  // namespace stgf
